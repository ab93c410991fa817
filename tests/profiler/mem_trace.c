/*
 * mem_trace: a QEMU TCG plugin that streams, while "armed", the guest's
 * instruction-fetch and data addresses, for a model of a board's memory path
 * (tests/src/memory/).
 *
 * Arming as in insn_profile.c: armed when the instruction at `begin` executes,
 * disarmed when the one at `end` executes; the `begin` instruction is counted,
 * the `end` one is not.
 *
 * The stream is cut to 8-byte granules (the smallest cache line modelled, the
 * RP2350's XIP cache line). A fetch event is written for each run of
 * instructions in one granule with no data access among them: when an
 * instruction starts in another granule, and before each data event. A data
 * event is written when a load or store touches another granule, or is of
 * another kind, than the data access before it, or when a fetch of another
 * granule came between. What is merged is only an access to the granule its
 * stream used last with nothing but accesses to one other granule between:
 * a hit in any cache whose lines are whole granules (nothing was filled in
 * between), though the recency order it leaves may differ (see
 * tests/src/memory/mod.rs).
 *
 * Arguments (QEMU 7.2 syntax: `-plugin mem_trace.so,begin=0x..,end=0x..,out=FILE`):
 *   begin=ADDR  end=ADDR  (C integer syntax; the Thumb bit is ignored)
 *   out=FILE    opened at start (a FIFO the reader drains while qemu runs, or a
 *               file) and written as the guest runs: records of two
 *               little-endian u32 words,
 *                 word 0: granule address | kind (bits 0-1: 0 fetch, 1 load, 2 store;
 *                         3: the end-of-span marker, written at each disarming)
 *                 word 1: for a fetch, the instructions executed since the last
 *                         fetch event, this one's first included (at least 1);
 *                         for a load or store, the access's size in bytes (of
 *                         the first access, when several were merged); 0 for a
 *                         marker.
 *               At exit one last record: word 0 = 0xffffffff, word 1 = how many
 *               times the plugin was armed (its `arms`).
 *
 * State is global: the machines traced have a single vCPU.
 *
 * Build: gcc -shared -fPIC -O2 -Wall -Wextra -o mem_trace.so mem_trace.c (plugin.h beside it)
 */
#include "plugin.h" /* the plugin API, the arguments */

EXPORT int qemu_plugin_version = 1;

/* The memory-callback part of QEMU 7.2's plugin API (version 1). */
typedef uint32_t qemu_plugin_meminfo_t;
enum qemu_plugin_mem_rw {
    QEMU_PLUGIN_MEM_R = 1,
    QEMU_PLUGIN_MEM_W,
    QEMU_PLUGIN_MEM_RW,
};
typedef void (*qemu_plugin_vcpu_mem_cb_t)(unsigned int vcpu_index, qemu_plugin_meminfo_t info, uint64_t vaddr,
                                          void *userdata);
void qemu_plugin_register_vcpu_mem_cb(struct qemu_plugin_insn *insn, qemu_plugin_vcpu_mem_cb_t cb,
                                      enum qemu_plugin_cb_flags flags, enum qemu_plugin_mem_rw rw, void *userdata);
unsigned int qemu_plugin_mem_size_shift(qemu_plugin_meminfo_t info);
bool qemu_plugin_mem_is_store(qemu_plugin_meminfo_t info);

#define GRANULE_MASK (~(uint64_t)7)
#define KIND_FETCH 0u
#define KIND_LOAD 1u
#define KIND_STORE 2u
#define KIND_MARK 3u

static uint64_t begin_pc = UINT64_MAX, end_pc = UINT64_MAX;
static FILE *out;
static bool armed;
static uint64_t arms;
/* The granule of the last fetch event and the instructions since it. */
static uint64_t fetch_granule = UINT64_MAX;
static uint32_t since_fetch;
/* The granule and kind of the last data event. */
static uint64_t data_granule = UINT64_MAX;
static uint32_t data_kind = UINT32_MAX;

static void emit(uint32_t w0, uint32_t w1)
{
    uint32_t rec[2] = {w0, w1};
    if (fwrite(rec, sizeof rec, 1, out) != 1) {
        fprintf(stderr, "mem_trace: write failed\n");
        abort();
    }
}

/* Writes the pending fetch event, if any. */
static void flush_fetch(void)
{
    if (since_fetch) {
        emit((uint32_t)fetch_granule | KIND_FETCH, since_fetch);
        since_fetch = 0;
    }
}

static void on_exec(unsigned int vcpu, void *udata)
{
    uint64_t pc = (uint64_t)(uintptr_t)udata;
    (void)vcpu;
    if (pc == begin_pc) {
        if (armed) {
            /* Armed again without the end marker: close the span before. */
            flush_fetch();
            emit(KIND_MARK, 0);
        }
        arms++;
        armed = true;
        fetch_granule = UINT64_MAX;
        data_granule = UINT64_MAX;
    } else if (pc == end_pc && armed) {
        flush_fetch();
        emit(KIND_MARK, 0);
        armed = false;
    }
    if (!armed) {
        return;
    }
    uint64_t g = pc & GRANULE_MASK;
    if (g != fetch_granule) {
        /* The fetch event is written when the next one starts, with its count;
           the next data access is written whatever granule it touches, since a
           fetch of another granule came between (a cache both streams share
           may have lost its line). */
        flush_fetch();
        fetch_granule = g;
        data_granule = UINT64_MAX;
    }
    since_fetch++;
}

static void on_mem(unsigned int vcpu, qemu_plugin_meminfo_t info, uint64_t vaddr, void *udata)
{
    (void)vcpu;
    (void)udata;
    if (!armed) {
        return;
    }
    uint64_t g = vaddr & GRANULE_MASK;
    uint32_t kind = qemu_plugin_mem_is_store(info) ? KIND_STORE : KIND_LOAD;
    if (g == data_granule && kind == data_kind) {
        return;
    }
    /* The fetch that issued this access comes first in the stream. */
    flush_fetch();
    data_granule = g;
    data_kind = kind;
    emit((uint32_t)g | kind, 1u << qemu_plugin_mem_size_shift(info));
}

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    size_t n = qemu_plugin_tb_n_insns(tb);
    (void)id;
    for (size_t i = 0; i < n; i++) {
        struct qemu_plugin_insn *qi = qemu_plugin_tb_get_insn(tb, i);
        void *pc = (void *)(uintptr_t)qemu_plugin_insn_vaddr(qi);
        qemu_plugin_register_vcpu_insn_exec_cb(qi, on_exec, QEMU_PLUGIN_CB_NO_REGS, pc);
        qemu_plugin_register_vcpu_mem_cb(qi, on_mem, QEMU_PLUGIN_CB_NO_REGS, QEMU_PLUGIN_MEM_RW, NULL);
    }
}

static void on_exit_close(qemu_plugin_id_t id, void *udata)
{
    (void)id;
    (void)udata;
    if (armed) {
        flush_fetch();
    }
    emit(0xffffffffu, (uint32_t)arms);
    if (fclose(out) != 0) {
        fprintf(stderr, "mem_trace: error closing the output\n");
    }
}

EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info, int argc, char **argv)
{
    (void)info;
    Markers m;
    if (!parse_markers("mem_trace", argc, argv, &m)) {
        return 1;
    }
    begin_pc = m.begin;
    end_pc = m.end;
    out = fopen(m.out, "wb");
    if (!out) {
        fprintf(stderr, "mem_trace: cannot open %s\n", m.out);
        return 1;
    }
    setvbuf(out, NULL, _IOFBF, 1 << 20);
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
    qemu_plugin_register_atexit_cb(id, on_exit_close, NULL);
    return 0;
}
