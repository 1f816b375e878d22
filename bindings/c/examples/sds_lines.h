/*
 * sds_lines: the text lines the Rust tools print for a replay (`monitor_replay`, the Rust
 * firmware), written from the C API's structs:
 *
 *   event {json}     one per event
 *   summary {json}   the route summary
 *   pins {json}      what a vehicle's two output pins did (alarm, comfort)
 *
 * JSON as the host tool writes it (serde field names and order; floats in the shortest form
 * that reads back to the same bits, by sds_format_f32). No printf and no allocation, so the
 * same file runs on the host and on a Cortex-M without a C library.
 */
#ifndef SDS_LINES_H
#define SDS_LINES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sds_monitor.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Longest line these functions write, with its newline and NUL. */
#define SDS_LINE_MAX 640

/*
 * The two output pins of a vehicle-side monitor, driven by events alone: the alarm pin latches
 * high on a collision without deceleration or a critical lateral chunk; the comfort pin is high
 * while the last comfort chunk failed.
 */
typedef struct sds_pins {
  bool alarm;
  uint32_t alarm_rises;
  bool comfort;
  uint32_t comfort_rises;
} sds_pins;

/* Applies one event to the pins. */
void sds_pins_see(sds_pins *pins, const sds_event *event);

/*
 * Each writes one line ("event {...}\n" and so on) NUL-terminated into out[0 .. cap] and
 * returns its length without the NUL, or 0 when it does not fit (or the event kind is unknown).
 */
size_t sds_line_event(char *out, size_t cap, const sds_event *event);
size_t sds_line_summary(char *out, size_t cap, const sds_summary *summary);
size_t sds_line_pins(char *out, size_t cap, const sds_pins *pins);
/* "NAME N\n", e.g. "route 3\n". */
size_t sds_line_u32(char *out, size_t cap, const char *name, uint32_t n);

#ifdef __cplusplus
}
#endif

#endif /* SDS_LINES_H */
