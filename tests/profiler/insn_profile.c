/*
 * insn_profile: a QEMU TCG plugin that counts, per guest PC, how often each
 * instruction executed and how often the instruction executed after it was not
 * the next one in memory (a taken branch, or an exception entry), while "armed".
 *
 * Arming: the plugin is armed when the instruction at `begin` executes and
 * disarmed when the one at `end` executes (the first instructions of two marker
 * functions in the firmware). The `begin` instruction is counted, the `end` one
 * is not, so with markers called around `render_tile` the count covers the
 * marker call, the call of `render_tile` and everything it executes.
 *
 * Arguments (QEMU 7.2 syntax: `-plugin insn_profile.so,begin=0x..,end=0x..,out=FILE`):
 *   begin=ADDR  end=ADDR  (C integer syntax, e.g. 0x1234; the Thumb bit is ignored)
 *   out=FILE    written at exit: `#` header lines, then one line per executed PC,
 *               sorted by PC: `pc count taken size disassembly` (pc in hex).
 *
 * Counting uses one exec callback per instruction (exact: QEMU calls it once each
 * time the instruction executes, whatever the translation blocks look like).
 * State is global: mps2-an386 has a single vCPU.
 *
 * Build: gcc -shared -fPIC -O2 -Wall -Wextra -o insn_profile.so insn_profile.c (plugin.h beside it)
 */
#include "plugin.h" /* the plugin API, the arguments */

EXPORT int qemu_plugin_version = 1;

/* One guest instruction, shared by every translation of its PC. */
typedef struct Insn {
    uint64_t pc;
    uint64_t count; /* executions while armed */
    uint64_t taken; /* of those, followed by an instruction other than pc + size */
    uint32_t size;
    char *disas;    /* from qemu_plugin_insn_disas, kept until exit */
} Insn;

static uint64_t begin_pc = UINT64_MAX, end_pc = UINT64_MAX;
static const char *out_path;
static bool armed;
static Insn *prev;                /* last counted instruction, while its successor is unknown */
static uint64_t arms, rearms, total;

/* Open-addressing hash table PC -> Insn*, capacity a power of two, at most half full. */
static Insn **table;
static size_t cap, used;

static size_t slot(uint64_t pc, size_t mask)
{
    size_t h = (size_t)((pc >> 1) * 0x9E3779B97F4A7C15ull) & mask;
    while (table[h] && table[h]->pc != pc) {
        h = (h + 1) & mask;
    }
    return h;
}

static Insn *lookup(uint64_t pc)
{
    if (2 * (used + 1) > cap) {
        Insn **old = table;
        size_t old_cap = cap;
        cap = cap ? 2 * cap : 4096;
        table = calloc(cap, sizeof *table);
        if (!table) {
            abort();
        }
        for (size_t i = 0; i < old_cap; i++) {
            if (old[i]) {
                table[slot(old[i]->pc, cap - 1)] = old[i];
            }
        }
        free(old);
    }
    size_t h = slot(pc, cap - 1);
    if (!table[h]) {
        table[h] = calloc(1, sizeof(Insn));
        if (!table[h]) {
            abort();
        }
        table[h]->pc = pc;
        used++;
    }
    return table[h];
}

static void on_exec(unsigned int vcpu, void *udata)
{
    Insn *in = udata;
    (void)vcpu;
    if (prev) {
        if (in->pc != prev->pc + prev->size) {
            prev->taken++;
        }
        prev = NULL;
    }
    if (in->pc == begin_pc) {
        rearms += armed;
        arms++;
        armed = true;
    } else if (in->pc == end_pc) {
        armed = false;
    }
    if (armed) {
        in->count++;
        total++;
        prev = in;
    }
}

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    size_t n = qemu_plugin_tb_n_insns(tb);
    (void)id;
    for (size_t i = 0; i < n; i++) {
        struct qemu_plugin_insn *qi = qemu_plugin_tb_get_insn(tb, i);
        Insn *in = lookup(qemu_plugin_insn_vaddr(qi));
        if (!in->disas) {
            in->size = (uint32_t)qemu_plugin_insn_size(qi);
            in->disas = qemu_plugin_insn_disas(qi);
        }
        qemu_plugin_register_vcpu_insn_exec_cb(qi, on_exec, QEMU_PLUGIN_CB_NO_REGS, in);
    }
}

static int by_pc(const void *a, const void *b)
{
    uint64_t x = (*(Insn *const *)a)->pc, y = (*(Insn *const *)b)->pc;
    return (x > y) - (x < y);
}

static void on_exit_write(qemu_plugin_id_t id, void *udata)
{
    size_t n = 0;
    (void)id;
    (void)udata;
    for (size_t i = 0; i < cap; i++) {
        if (table[i] && table[i]->count) {
            table[n++] = table[i];
        }
    }
    qsort(table, n, sizeof *table, by_pc);
    FILE *f = fopen(out_path, "w");
    if (!f) {
        fprintf(stderr, "insn_profile: cannot write %s\n", out_path);
        return;
    }
    fprintf(f, "# insn_profile begin=0x%" PRIx64 " end=0x%" PRIx64 "\n", begin_pc, end_pc);
    fprintf(f, "# arms=%" PRIu64 " rearms=%" PRIu64 " armed_at_exit=%d total=%" PRIu64 " pcs=%zu\n", arms,
            rearms, armed, total, n);
    fprintf(f, "# pc count taken size disassembly\n");
    for (size_t i = 0; i < n; i++) {
        const Insn *in = table[i];
        const char *d = in->disas ? in->disas : "?";
        fprintf(f, "0x%" PRIx64 " %" PRIu64 " %" PRIu64 " %" PRIu32 " ", in->pc, in->count, in->taken, in->size);
        for (; *d; d++) { /* one line per instruction, whatever the disassembler printed */
            fputc(*d == '\n' || *d == '\t' ? ' ' : *d, f);
        }
        fputc('\n', f);
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "insn_profile: error writing %s\n", out_path);
    }
}

EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info, int argc, char **argv)
{
    (void)info;
    Markers m;
    if (!parse_markers("insn_profile", argc, argv, &m)) {
        return 1;
    }
    begin_pc = m.begin;
    end_pc = m.end;
    out_path = m.out;
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
    qemu_plugin_register_atexit_cb(id, on_exit_write, NULL);
    return 0;
}
