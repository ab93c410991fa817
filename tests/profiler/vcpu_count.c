/*
 * vcpu_count: a QEMU TCG plugin that counts each vCPU's executed instructions
 * between two marker functions, span by span (the dual-core firmware image,
 * tests/dualcore, calls the markers around each CPU's tile loop).
 *
 * Arming is per vCPU: a vCPU is armed when it executes the instruction at `begin`
 * and disarmed when it executes the one at `end` (the first instructions of two
 * marker functions). The `begin` instruction is counted, the `end` one is not (as
 * insn_profile.c counts). Each disarming closes a span: the vCPU's count since its
 * arming, and of those the instructions it executed while another vCPU was armed
 * too (`shared`: with two vCPUs working side by side, how evenly qemu shared the
 * time between them).
 *
 * Arguments (QEMU 7.2 syntax: `-plugin vcpu_count.so,begin=0x..,end=0x..,out=FILE`):
 *   begin=ADDR  end=ADDR  (C integer syntax; the Thumb bit is ignored)
 *   out=FILE    written at exit:
 *     `# vcpu_count begin=0x.. end=0x..`
 *     one line per vCPU that executed anything, by index:
 *       `vcpu=<i> arms=<n> rearms=<n> armed_at_exit=<0|1> spans=<n> counted=<n>
 *        executed=<n> switches=<n>`
 *       (executed: every instruction of that vCPU, armed or not; switches: how
 *       often execution passed to this vCPU from another one)
 *     then one line per span, in the order the spans closed:
 *       `span vcpu=<i> insns=<n> shared=<n>`
 *
 * Counting uses one exec callback per instruction (exact, whatever the
 * translation blocks look like). The state is global: qemu runs the vCPUs on one
 * thread under `-icount` (the harness always passes it).
 *
 * Build: gcc -shared -fPIC -O2 -Wall -Wextra -o vcpu_count.so vcpu_count.c (plugin.h beside it)
 */
#include "plugin.h" /* the plugin API, the arguments */

EXPORT int qemu_plugin_version = 1;

#define MAX_VCPUS 8

/* One vCPU's counts. */
typedef struct Vcpu {
    bool armed;
    uint64_t count;  /* instructions of the open span */
    uint64_t shared; /* of those, executed while another vCPU was armed */
    uint64_t counted, executed, arms, rearms, switches;
    uint64_t (*spans)[2]; /* closed spans, in order: count, shared */
    size_t nspans, cap;
} Vcpu;

static Vcpu vcpus[MAX_VCPUS];
static uint64_t begin_pc = UINT64_MAX, end_pc = UINT64_MAX;
static const char *out_path;
/* The vCPU that executed the last instruction (for `switches` only). */
static unsigned int last_vcpu = UINT32_MAX;
/* How many vCPUs are armed. */
static unsigned int armed_now;

/* The order in which spans closed, over all vCPUs: one vCPU index per span. */
static unsigned int *order;
static size_t norder, order_cap;

static Vcpu *vcpu_of(unsigned int i)
{
    if (i >= MAX_VCPUS) {
        fprintf(stderr, "vcpu_count: vCPU %u, at most %d supported\n", i, MAX_VCPUS);
        abort();
    }
    Vcpu *v = &vcpus[i];
    v->executed++;
    if (i != last_vcpu) {
        v->switches++;
        last_vcpu = i;
    }
    return v;
}

static void on_insn(unsigned int vcpu, void *udata)
{
    Vcpu *v = vcpu_of(vcpu);
    (void)udata;
    if (v->armed) {
        v->count++;
        v->shared += armed_now > 1;
    }
}

static void on_begin(unsigned int vcpu, void *udata)
{
    Vcpu *v = vcpu_of(vcpu);
    (void)udata;
    v->rearms += v->armed;
    v->arms++;
    armed_now += !v->armed;
    v->armed = true;
    v->count = 1; /* the begin instruction */
    v->shared = armed_now > 1;
}

static void on_end(unsigned int vcpu, void *udata)
{
    Vcpu *v = vcpu_of(vcpu);
    (void)udata;
    if (!v->armed) {
        return;
    }
    v->armed = false;
    armed_now--;
    if (v->nspans == v->cap) {
        v->cap = v->cap ? 2 * v->cap : 64;
        v->spans = realloc(v->spans, v->cap * sizeof *v->spans);
        if (!v->spans) {
            abort();
        }
    }
    v->spans[v->nspans][0] = v->count;
    v->spans[v->nspans][1] = v->shared;
    v->nspans++;
    v->counted += v->count;
    v->count = 0;
    v->shared = 0;
    if (norder == order_cap) {
        order_cap = order_cap ? 2 * order_cap : 64;
        order = realloc(order, order_cap * sizeof *order);
        if (!order) {
            abort();
        }
    }
    order[norder++] = vcpu;
}

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    size_t n = qemu_plugin_tb_n_insns(tb);
    (void)id;
    for (size_t i = 0; i < n; i++) {
        struct qemu_plugin_insn *qi = qemu_plugin_tb_get_insn(tb, i);
        uint64_t pc = qemu_plugin_insn_vaddr(qi);
        qemu_plugin_vcpu_udata_cb_t cb = on_insn;
        if (pc == begin_pc) {
            cb = on_begin;
        } else if (pc == end_pc) {
            cb = on_end;
        }
        qemu_plugin_register_vcpu_insn_exec_cb(qi, cb, QEMU_PLUGIN_CB_NO_REGS, NULL);
    }
}

static void on_exit_write(qemu_plugin_id_t id, void *udata)
{
    (void)id;
    (void)udata;
    FILE *f = fopen(out_path, "w");
    if (!f) {
        fprintf(stderr, "vcpu_count: cannot write %s\n", out_path);
        return;
    }
    fprintf(f, "# vcpu_count begin=0x%" PRIx64 " end=0x%" PRIx64 "\n", begin_pc, end_pc);
    for (unsigned int i = 0; i < MAX_VCPUS; i++) {
        const Vcpu *v = &vcpus[i];
        if (!v->executed) {
            continue;
        }
        fprintf(f,
                "vcpu=%u arms=%" PRIu64 " rearms=%" PRIu64 " armed_at_exit=%d spans=%zu counted=%" PRIu64
                " executed=%" PRIu64 " switches=%" PRIu64 "\n",
                i, v->arms, v->rearms, v->armed, v->nspans, v->counted, v->executed, v->switches);
    }
    size_t next[MAX_VCPUS] = {0};
    for (size_t k = 0; k < norder; k++) {
        unsigned int i = order[k];
        const uint64_t *span = vcpus[i].spans[next[i]++];
        fprintf(f, "span vcpu=%u insns=%" PRIu64 " shared=%" PRIu64 "\n", i, span[0], span[1]);
    }
    if (fclose(f) != 0) {
        fprintf(stderr, "vcpu_count: error writing %s\n", out_path);
    }
}

EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info, int argc, char **argv)
{
    (void)info;
    Markers m;
    if (!parse_markers("vcpu_count", argc, argv, &m)) {
        return 1;
    }
    begin_pc = m.begin;
    end_pc = m.end;
    out_path = m.out;
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
    qemu_plugin_register_atexit_cb(id, on_exit_write, NULL);
    return 0;
}
