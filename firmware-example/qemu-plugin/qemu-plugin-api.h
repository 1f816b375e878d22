/*
 * The part of QEMU's TCG plugin API that insncount.c uses, declared from QEMU's plugin
 * documentation (docs/devel/tcg-plugins in QEMU; "QEMU TCG Plugins" on qemu.org): Debian's
 * QEMU packages ship no qemu-plugin.h to include.
 *
 * Everything here is part of plugin API version 2 (QEMU 9.0, which introduced per-vCPU
 * scoreboards and inline operations on them) and unchanged through version 4 (QEMU 10.0, the
 * version run-tests.sh is tested with). QEMU checks the exported qemu_plugin_version against
 * its own accepted range when it loads the plugin.
 */
#ifndef INSNCOUNT_QEMU_PLUGIN_API_H
#define INSNCOUNT_QEMU_PLUGIN_API_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define INSNCOUNT_PLUGIN_API 2

#define QEMU_PLUGIN_EXPORT __attribute__((visibility("default")))

typedef uint64_t qemu_plugin_id_t;

/* What QEMU tells the plugin at install time (only valid during qemu_plugin_install). */
typedef struct qemu_info_t {
    const char *target_name;
    struct {
        int min; /* oldest plugin API version QEMU accepts */
        int cur; /* newest */
    } version;
    bool system_emulation;
    union {
        struct {
            int smp_vcpus;
            int max_vcpus;
        } system;
    };
} qemu_info_t;

/* Opaque handles. */
struct qemu_plugin_tb;
struct qemu_plugin_scoreboard;

/* A uint64_t field at `offset` inside every vCPU's entry of a scoreboard. */
typedef struct {
    struct qemu_plugin_scoreboard *score;
    size_t offset;
} qemu_plugin_u64;

enum qemu_plugin_op {
    QEMU_PLUGIN_INLINE_ADD_U64,
    QEMU_PLUGIN_INLINE_STORE_U64,
};

typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id, struct qemu_plugin_tb *tb);
typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void *userdata);

/* The entry point QEMU calls when it loads the plugin; non-zero refuses the load. */
QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info, int argc,
                                           char **argv);

/* Called for every block QEMU translates. */
void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id, qemu_plugin_vcpu_tb_trans_cb_t cb);
/* Called once when the emulation ends. */
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, qemu_plugin_udata_cb_t cb, void *userdata);

/* Number of guest instructions in a translated block. */
size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb *tb);
/* Emits `entry op= imm` (for the executing vCPU) at the block's entry, as generated code. */
void qemu_plugin_register_vcpu_tb_exec_inline_per_vcpu(struct qemu_plugin_tb *tb,
                                                       enum qemu_plugin_op op,
                                                       qemu_plugin_u64 entry, uint64_t imm);

/* Per-vCPU storage, entries of `element_size` bytes, zero-initialised, grown by QEMU. */
struct qemu_plugin_scoreboard *qemu_plugin_scoreboard_new(size_t element_size);
void qemu_plugin_scoreboard_free(struct qemu_plugin_scoreboard *score);
/* Sum of `entry` over all vCPUs. */
uint64_t qemu_plugin_u64_sum(qemu_plugin_u64 entry);

/* Writes a string to QEMU's log (stderr unless -D FILE). */
void qemu_plugin_outs(const char *string);

#endif
