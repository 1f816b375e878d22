/*
 * frames_jsonl: reads the frames file `sds frames` writes (one JSON frame per line) into
 * sds_frame structs, for the host examples and tests.
 *
 *   {"a_lon":-1.5,"a_lat":0.25,"a_mag":1.6,"yaw_rate":2.0,"speed":7.0,"lat_err":null,
 *    "collisions":{"pedestrian":0,"vehicle":1,"layout":0,"workzone":0}}
 *
 * Keys in any order; "lat_err" null or absent means unknown; absent collision counts are 0.
 * The "host" object `sds frames` adds (the host's values behind the frame) is skipped.
 * Numbers are read with strtof, which rounds correctly, as Rust's parser does: the same text
 * gives the same bits.
 */
#ifndef FRAMES_JSONL_H
#define FRAMES_JSONL_H

#include <stddef.h>

#include "sds_monitor.h"

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Parses one line into *frame. Returns NULL on success, or a static message saying what is
 * wrong (the caller adds the file and line). Does not validate values (the monitor does).
 */
const char *sds_frame_parse_json(const char *line, sds_frame *frame);

#ifdef __cplusplus
}
#endif

#endif /* FRAMES_JSONL_H */
