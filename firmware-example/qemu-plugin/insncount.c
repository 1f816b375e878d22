/*
 * insncount: a QEMU TCG plugin that counts the guest instructions a run executes.
 *
 * The firmware tests (firmware-example/run-tests.sh) load it into qemu-system-arm to measure
 * instructions per frame: they run the firmware for N and for M frames and take the difference
 * of the two totals, so the plugin only has to report one exact total per run.
 *
 * How it counts: whenever QEMU translates a block of guest code, the plugin learns how many
 * instructions the block holds and asks QEMU to emit two inline additions at the block's entry
 * (instructions += n, blocks += 1) into a per-vCPU scoreboard. Inline additions run as generated
 * code, with no call into the plugin per block. At exit the per-vCPU entries are summed.
 * A block is counted whole when it is entered; with `-icount shift=0` QEMU ends blocks where the
 * instruction budget runs out, so every run of the same image gives the same total.
 *
 * Output, at exit: "insns: N" and "tbs: M" lines, into the file named by `out=FILE`, or through
 * QEMU's log (qemu_plugin_outs; shown with `-d plugin`) when no file is given.
 *
 * Build:  gcc -shared -fPIC -O2 -Wall -Wextra -o libinsncount.so insncount.c
 * Use:    qemu-system-arm ... -icount shift=0 -plugin ./libinsncount.so,out=insns.txt
 *
 * Debian's QEMU packages ship no qemu-plugin.h, so qemu-plugin-api.h beside this file declares
 * the part of QEMU's documented plugin API that this plugin uses (API version 2).
 */
#include <stdio.h>
#include <string.h>

#include "qemu-plugin-api.h"

/* The API version this plugin is written against; QEMU refuses to load a plugin whose version
 * is outside its own [min, cur] range (QEMU 9.0 to 10.x accept 2). */
QEMU_PLUGIN_EXPORT int qemu_plugin_version = INSNCOUNT_PLUGIN_API;

/* One scoreboard entry per vCPU. */
struct counts {
    uint64_t insns;
    uint64_t tbs;
};

static struct qemu_plugin_scoreboard *board;
static qemu_plugin_u64 insns_of;
static qemu_plugin_u64 tbs_of;
static const char *out_path; /* argv outlives the plugin, so pointing into it is fine */

static void on_translate(qemu_plugin_id_t id, struct qemu_plugin_tb *tb)
{
    (void)id;
    qemu_plugin_register_vcpu_tb_exec_inline_per_vcpu(tb, QEMU_PLUGIN_INLINE_ADD_U64, insns_of,
                                                      qemu_plugin_tb_n_insns(tb));
    qemu_plugin_register_vcpu_tb_exec_inline_per_vcpu(tb, QEMU_PLUGIN_INLINE_ADD_U64, tbs_of, 1);
}

static void report_at_exit(qemu_plugin_id_t id, void *unused)
{
    (void)id;
    (void)unused;
    char text[96];
    snprintf(text, sizeof text, "insns: %llu\ntbs: %llu\n",
             (unsigned long long)qemu_plugin_u64_sum(insns_of),
             (unsigned long long)qemu_plugin_u64_sum(tbs_of));
    qemu_plugin_scoreboard_free(board);
    if (out_path == NULL) {
        qemu_plugin_outs(text);
        return;
    }
    FILE *f = fopen(out_path, "w");
    if (f == NULL || fputs(text, f) < 0 || fclose(f) != 0) {
        /* Leave no partial file behind: the caller reads a missing count as a failure. */
        fprintf(stderr, "insncount: cannot write %s\n", out_path);
        if (f != NULL) remove(out_path);
    }
}

QEMU_PLUGIN_EXPORT int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t *info, int argc,
                                           char **argv)
{
    if (info->version.min > INSNCOUNT_PLUGIN_API || info->version.cur < INSNCOUNT_PLUGIN_API) {
        fprintf(stderr, "insncount: QEMU offers plugin API %d..%d, this plugin needs %d\n",
                info->version.min, info->version.cur, INSNCOUNT_PLUGIN_API);
        return -1;
    }
    for (int i = 0; i < argc; i++) {
        if (strncmp(argv[i], "out=", 4) == 0 && argv[i][4] != '\0') {
            out_path = argv[i] + 4;
        } else {
            fprintf(stderr, "insncount: unknown argument '%s' (the only one is out=FILE)\n",
                    argv[i]);
            return -1;
        }
    }
    board = qemu_plugin_scoreboard_new(sizeof(struct counts));
    insns_of = (qemu_plugin_u64){board, offsetof(struct counts, insns)};
    tbs_of = (qemu_plugin_u64){board, offsetof(struct counts, tbs)};
    qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
    qemu_plugin_register_atexit_cb(id, report_at_exit, NULL);
    return 0;
}
