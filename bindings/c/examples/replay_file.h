/*
 * replay_file: one route's frames file through the C API, printing the lines `monitor_replay`
 * prints (route, event, summary, pins) to stdout. Shared by the example and the C test.
 */
#ifndef REPLAY_FILE_H
#define REPLAY_FILE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/*
 * Replays the frames file at `path` as route number `index` with a fresh monitor (default
 * configuration). Returns 1, or 0 after printing why to stderr (file and line named).
 */
int sds_replay_file(uint32_t index, const char *path);

#ifdef __cplusplus
}
#endif

#endif /* REPLAY_FILE_H */
