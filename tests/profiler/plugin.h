/*
 * What the repository's QEMU TCG plugins share (insn_profile.c, vcpu_count.c):
 * the part of QEMU's plugin API they use and the parsing of their arguments.
 *
 * The API (include/qemu/qemu-plugin.h, API version 1 as shipped by QEMU 7.2):
 * Debian installs no header, so the declarations are written here; they follow
 * the stable C ABI of that version.
 *
 * The arguments, in QEMU 7.2's syntax `-plugin NAME.so,begin=0x..,end=0x..,out=FILE`:
 *   begin=ADDR  end=ADDR  the first instructions of the two marker functions
 *                         (C integer syntax, e.g. 0x1234; the Thumb bit is ignored)
 *   out=FILE    where the plugin writes at exit
 */
#ifndef TESSERA_PLUGIN_H
#define TESSERA_PLUGIN_H

#include <inttypes.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef uint64_t qemu_plugin_id_t;
struct qemu_plugin_tb;
struct qemu_plugin_insn;
typedef struct qemu_info_t {
    const char *target_name;
    struct {
        int min;
        int cur;
    } version;
    /* further fields (system_emulation, vCPU counts) are not read */
} qemu_info_t;
enum qemu_plugin_cb_flags {
    QEMU_PLUGIN_CB_NO_REGS,
    QEMU_PLUGIN_CB_R_REGS,
    QEMU_PLUGIN_CB_RW_REGS,
};
typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);
typedef void (*qemu_plugin_vcpu_udata_cb_t)(unsigned int vcpu_index, void *userdata);
typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id, struct qemu_plugin_tb *tb);

void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id, qemu_plugin_vcpu_tb_trans_cb_t cb);
void qemu_plugin_register_vcpu_insn_exec_cb(struct qemu_plugin_insn *insn, qemu_plugin_vcpu_udata_cb_t cb,
                                            enum qemu_plugin_cb_flags flags, void *userdata);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, qemu_plugin_udata_cb_t cb, void *userdata);
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
struct qemu_plugin_insn *qemu_plugin_tb_get_insn(const struct qemu_plugin_tb *tb, size_t idx);
uint64_t qemu_plugin_insn_vaddr(const struct qemu_plugin_insn *insn);
size_t qemu_plugin_insn_size(const struct qemu_plugin_insn *insn);
char *qemu_plugin_insn_disas(const struct qemu_plugin_insn *insn);

#define EXPORT __attribute__((visibility("default")))

/* The markers' addresses and the output file, from the plugin's arguments. */
typedef struct Markers {
    uint64_t begin;
    uint64_t end;
    const char *out;
} Markers;

/*
 * Reads `begin=`, `end=` and `out=` from the arguments into `m`; false (with
 * a message naming the plugin `name` on stderr) when one is unknown or missing,
 * or the two addresses are the same.
 */
static inline bool parse_markers(const char *name, int argc, char **argv, Markers *m)
{
    m->begin = UINT64_MAX;
    m->end = UINT64_MAX;
    m->out = NULL;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i];
        if (strncmp(a, "begin=", 6) == 0) {
            m->begin = strtoull(a + 6, NULL, 0) & ~1ull;
        } else if (strncmp(a, "end=", 4) == 0) {
            m->end = strtoull(a + 4, NULL, 0) & ~1ull;
        } else if (strncmp(a, "out=", 4) == 0) {
            m->out = strdup(a + 4);
        } else {
            fprintf(stderr, "%s: unknown argument %s (want begin=, end=, out=)\n", name, a);
            return false;
        }
    }
    if (m->begin == UINT64_MAX || m->end == UINT64_MAX || !m->out || m->begin == m->end) {
        fprintf(stderr, "%s: need begin=ADDR end=ADDR (distinct) and out=FILE\n", name);
        return false;
    }
    return true;
}

#endif
