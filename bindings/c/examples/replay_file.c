/* replay_file.c: see replay_file.h. */
#include "replay_file.h"

#include <stdio.h>
#include <string.h>

#include "frames_jsonl.h"
#include "sds_lines.h"
#include "sds_monitor.h"

/* Caller-owned monitor memory: no allocation anywhere. */
static sds_monitor_storage storage;

static int emit(const char *line, size_t n) {
  return n > 0 && fwrite(line, 1, n, stdout) == n;
}

static int emit_events(const sds_events *events, sds_pins *pins) {
  char line[SDS_LINE_MAX];
  for (uint32_t i = 0; i < events->len; i++) {
    sds_pins_see(pins, &events->events[i]);
    if (!emit(line, sds_line_event(line, sizeof line, &events->events[i]))) {
      return 0;
    }
  }
  return 1;
}

int sds_replay_file(uint32_t index, const char *path) {
  char line[SDS_LINE_MAX];
  char raw[4096];
  unsigned long number = 0;
  sds_monitor *monitor = (sds_monitor *)&storage;
  sds_config config = sds_config_default();
  sds_pins pins;
  sds_events events;
  sds_summary summary;
  sds_result r;
  FILE *f = fopen(path, "r");

  memset(&pins, 0, sizeof pins);
  if (f == NULL) {
    fprintf(stderr, "sds_replay: %s: cannot open\n", path);
    return 0;
  }
  r = sds_monitor_init(monitor, sizeof storage, &config);
  if (r != SDS_RESULT_OK) {
    fprintf(stderr, "sds_replay: sds_monitor_init: %s\n", sds_result_str(r));
    fclose(f);
    return 0;
  }
  if (!emit(line, sds_line_u32(line, sizeof line, "route", index))) {
    fclose(f);
    return 0;
  }
  while (fgets(raw, sizeof raw, f) != NULL) {
    sds_frame frame;
    const char *err;
    size_t len = strlen(raw);
    number++;
    if (len + 1 == sizeof raw && raw[len - 1] != '\n') {
      fprintf(stderr, "sds_replay: %s line %lu: longer than %zu bytes\n", path, number,
              sizeof raw - 2);
      fclose(f);
      return 0;
    }
    if (strspn(raw, " \t\r\n") == len) {
      continue; /* blank line */
    }
    err = sds_frame_parse_json(raw, &frame);
    if (err != NULL) {
      fprintf(stderr, "sds_replay: %s line %lu: %s\n", path, number, err);
      fclose(f);
      return 0;
    }
    r = sds_monitor_push(monitor, &frame, &events);
    if (r != SDS_RESULT_OK) {
      fprintf(stderr, "sds_replay: %s line %lu: %s\n", path, number, sds_result_str(r));
      fclose(f);
      return 0;
    }
    if (!emit_events(&events, &pins)) {
      fclose(f);
      return 0;
    }
  }
  if (ferror(f)) {
    fprintf(stderr, "sds_replay: %s: read error\n", path);
    fclose(f);
    return 0;
  }
  fclose(f);
  r = sds_monitor_finish(monitor, &events, &summary);
  if (r != SDS_RESULT_OK) {
    fprintf(stderr, "sds_replay: %s: %s\n", path, sds_result_str(r));
    return 0;
  }
  return emit_events(&events, &pins) &&
         emit(line, sds_line_summary(line, sizeof line, &summary)) &&
         emit(line, sds_line_pins(line, sizeof line, &pins));
}

