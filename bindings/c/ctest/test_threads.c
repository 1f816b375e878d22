/*
 * test_threads.c: the API has no shared state. Four threads each run their own monitor over the
 * same made-up route at once; each must get exactly the single-threaded summary and events.
 * run-tests.sh runs it under valgrind's helgrind (data races are errors).
 * The closing line on stderr is "c threads: N passed, M failed".
 */
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "sds_monitor.h"

#define THREADS 4
#define FRAMES 400

typedef struct run {
  sds_monitor_storage memory;
  sds_summary summary;
  uint32_t events;
  uint32_t checksum;
  sds_result result;
} run;

/* A route with braking, swerving, drift and two collisions, the same for every thread. */
static sds_frame frame_at(int i) {
  sds_frame f;
  memset(&f, 0, sizeof f);
  f.a_lon = (i % 50 < 10) ? -3.0f : 0.5f;
  f.a_lat = (i % 37 < 5) ? 5.5f : 0.2f;
  f.a_mag = f.a_lon < 0 ? 3.2f : 0.6f;
  f.yaw_rate = (float)(i % 23) * 2.5f;
  f.speed = 5.0f + (float)(i % 17) * 0.25f;
  f.lat_err = (float)(i % 41) * 0.03f;
  f.has_lat_err = i % 13 != 0;
  f.collisions.vehicle = i == 120 || i == 333;
  return f;
}

static void *replay(void *arg) {
  run *r = (run *)arg;
  sds_monitor *m = (sds_monitor *)&r->memory;
  sds_config c = sds_config_default();
  sds_events ev;
  r->result = sds_monitor_init(m, sizeof r->memory, &c);
  for (int i = 0; i < FRAMES && r->result == SDS_RESULT_OK; i++) {
    sds_frame f = frame_at(i);
    r->result = sds_monitor_push(m, &f, &ev);
    for (uint32_t k = 0; k < ev.len; k++) {
      r->events++;
      r->checksum = r->checksum * 31u + ev.events[k].kind * 7u + ev.events[k].comfort.chunk +
                    ev.events[k].lateral.chunk + ev.events[k].collision.frame;
    }
  }
  if (r->result == SDS_RESULT_OK) {
    r->result = sds_monitor_finish(m, &ev, &r->summary);
    r->events += ev.len;
  }
  return NULL;
}

static run reference;
static run runs[THREADS];

int main(void) {
  unsigned passed = 0, failed = 0;
  pthread_t threads[THREADS];
  replay(&reference);
  if (reference.result == SDS_RESULT_OK && reference.events > 0 && reference.summary.frames == FRAMES) {
    passed++;
  } else {
    failed++;
    fprintf(stderr, "test_threads: the reference run failed\n");
  }
  for (int t = 0; t < THREADS; t++) {
    if (pthread_create(&threads[t], NULL, replay, &runs[t]) != 0) {
      fprintf(stderr, "test_threads: pthread_create failed\n");
      return 1;
    }
  }
  for (int t = 0; t < THREADS; t++) {
    pthread_join(threads[t], NULL);
    if (runs[t].result == SDS_RESULT_OK &&
        memcmp(&runs[t].summary, &reference.summary, sizeof reference.summary) == 0 &&
        runs[t].events == reference.events && runs[t].checksum == reference.checksum) {
      passed++;
    } else {
      failed++;
      fprintf(stderr, "test_threads: thread %d differs from the single-threaded run\n", t);
    }
  }
  fprintf(stderr, "c threads: %u passed, %u failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
