/*
 * test_link.c: the live link's C API (sds_link_*) from C99 (gcc -std=c99 -Wall -Wextra -Werror,
 * linked statically against libsds_monitor.a, run under valgrind).
 *
 *   test_link FRAMES.jsonl...
 *
 * For each frames file: the doer's side encodes a start, every frame, a corrupted copy of the
 * middle frame (ERROR), a repeat of the next one (REPEATED) and an end with sds_link_encode_*;
 * the checker (sds_link_checker_*, caller-owned storage) takes the bytes in 7-byte pieces; its
 * answers, decoded with sds_link_decode, must carry exactly the events and the summary that
 * sds_monitor gives on the same frames, with the statuses counted as said. Then, on the same
 * checker: a doer that stops sending gives NONEWDATA at the deadline, a run of corrupted
 * messages a link_fault event and the pin (status.valid false), the next start link_restored.
 * Every error code the link API promises is checked too. The closing line on stderr is
 * "c link: N passed, M failed"; the exit status is 1 on a failure.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "frames_jsonl.h"
#include "sds_monitor.h"

/* The bytes on each side of the link. */
typedef struct {
  unsigned char *bytes;
  size_t len, cap;
} buffer;

static void put(buffer *b, const unsigned char *bytes, size_t len) {
  if (b->len + len > b->cap) {
    b->cap = 2 * (b->len + len);
    b->bytes = (unsigned char *)realloc(b->bytes, b->cap);
    if (b->bytes == NULL) {
      fprintf(stderr, "out of memory\n");
      exit(2);
    }
  }
  memcpy(b->bytes + b->len, bytes, len);
  b->len += len;
}

/* The checker's write function: its answers into a buffer. */
static void collect(void *ctx, const uint8_t *bytes, size_t len) { put((buffer *)ctx, bytes, len); }

/* The checker's answers, decoded; every one must pass its check. */
typedef struct {
  sds_link_message *m;
  size_t len;
} messages;

static messages decode_all(const buffer *b) {
  messages out = {NULL, 0};
  size_t start = 0;
  out.m = (sds_link_message *)calloc(b->len / 2 + 1, sizeof *out.m);
  if (out.m == NULL) exit(2);
  for (size_t i = 0; i < b->len; i++) {
    if (b->bytes[i] != 0) continue;
    sds_result r = sds_link_decode(b->bytes + start, i + 1 - start, &out.m[out.len]);
    CHECK_RESULT(r, SDS_RESULT_OK);
    if (r == SDS_RESULT_OK) out.len++;
    start = i + 1;
  }
  CHECK(start == b->len); /* the answers end with a whole message */
  return out;
}

static int same_event(const sds_event *a, const sds_event *b) {
  if (a->kind != b->kind) return 0;
  switch (a->kind) {
    case SDS_EVENT_COLLISION:
      return a->collision.frame == b->collision.frame && a->collision.speed == b->collision.speed &&
             a->collision.nodecel == b->collision.nodecel && a->collision.exempt == b->collision.exempt &&
             a->collision.collisions.vehicle == b->collision.collisions.vehicle &&
             a->collision.collisions.pedestrian == b->collision.collisions.pedestrian &&
             a->collision.collisions.layout == b->collision.collisions.layout;
    case SDS_EVENT_COMFORT:
      return a->comfort.chunk == b->comfort.chunk && a->comfort.frames == b->comfort.frames &&
             a->comfort.comfortable == b->comfort.comfortable &&
             memcmp(&a->comfort.failed, &b->comfort.failed, sizeof a->comfort.failed) == 0;
    case SDS_EVENT_LATERAL:
      return a->lateral.chunk == b->lateral.chunk && a->lateral.max_excess == b->lateral.max_excess &&
             a->lateral.band == b->lateral.band;
    default:
      return 0;
  }
}

static int same_summary(const sds_summary *a, const sds_summary *b) {
  return a->frames == b->frames && a->comfort.chunks == b->comfort.chunks &&
         a->comfort.comfortable == b->comfort.comfortable &&
         memcmp(&a->comfort.failed, &b->comfort.failed, sizeof a->comfort.failed) == 0 &&
         memcmp(&a->lateral, &b->lateral, sizeof a->lateral) == 0 &&
         memcmp(&a->collisions, &b->collisions, sizeof a->collisions) == 0;
}

static sds_frame *read_frames(const char *path, size_t *n) {
  FILE *f = fopen(path, "r");
  char line[4096];
  size_t cap = 256;
  sds_frame *frames = (sds_frame *)malloc(cap * sizeof *frames);
  *n = 0;
  if (f == NULL || frames == NULL) {
    fprintf(stderr, "%s: cannot read\n", path);
    exit(2);
  }
  while (fgets(line, sizeof line, f) != NULL) {
    if (line[0] == '\n' || line[0] == '\0') continue;
    if (*n == cap) {
      cap *= 2;
      frames = (sds_frame *)realloc(frames, cap * sizeof *frames);
      if (frames == NULL) exit(2);
    }
    const char *err = sds_frame_parse_json(line, &frames[*n]);
    if (err != NULL) {
      fprintf(stderr, "%s:%zu: %s\n", path, *n + 1, err);
      exit(2);
    }
    (*n)++;
  }
  fclose(f);
  return frames;
}

static sds_link_checker_storage checker_mem;
static sds_monitor_storage monitor_mem;
/* The doer's E2E counters, one per data id, running on across routes. */
static uint16_t c_start, c_frame, c_end;

static void encode_frame(buffer *wire, const sds_frame *f, uint16_t counter) {
  uint8_t msg[SDS_LINK_MAX_ENCODED];
  size_t n = 0;
  CHECK_RESULT(sds_link_encode_frame(f, counter, msg, sizeof msg, &n), SDS_RESULT_OK);
  CHECK(n == 47);
  put(wire, msg, n);
}

/* Feeds `wire` to the checker in 7-byte pieces, one frame period of clock per piece. */
static void feed(sds_link_checker *k, const buffer *wire, uint64_t *now_us, buffer *answers) {
  for (size_t i = 0; i < wire->len; i += 7) {
    size_t len = wire->len - i < 7 ? wire->len - i : 7;
    CHECK_RESULT(sds_link_receive(k, wire->bytes + i, len, *now_us, collect, answers), SDS_RESULT_OK);
    *now_us += 1000;
  }
}

/* One frames file: the checker's events and summary equal the monitor's. */
static void route(sds_link_checker *k, const char *path, uint64_t *now_us) {
  size_t n = 0;
  sds_frame *frames = read_frames(path, &n);
  if (n < 2) {
    fprintf(stderr, "%s: fewer than 2 frames\n", path);
    exit(2);
  }
  sds_config c = sds_config_default();
  /* The replay: the monitor on the same frames. */
  sds_monitor *m = (sds_monitor *)&monitor_mem;
  CHECK_RESULT(sds_monitor_init(m, sizeof monitor_mem, &c), SDS_RESULT_OK);
  sds_event *want = (sds_event *)calloc(3 * (n + 1), sizeof *want);
  size_t nwant = 0;
  sds_events ev;
  sds_summary want_summary;
  if (want == NULL) exit(2);
  for (size_t i = 0; i < n; i++) {
    CHECK_RESULT(sds_monitor_push(m, &frames[i], &ev), SDS_RESULT_OK);
    for (uint32_t j = 0; j < ev.len; j++) want[nwant++] = ev.events[j];
  }
  CHECK_RESULT(sds_monitor_finish(m, &ev, &want_summary), SDS_RESULT_OK);
  for (uint32_t j = 0; j < ev.len; j++) want[nwant++] = ev.events[j];

  /* The doer's bytes: start, the frames, with a corrupted copy and a repeat in the middle, end. */
  buffer wire = {NULL, 0, 0}, answers = {NULL, 0, 0};
  uint8_t msg[SDS_LINK_MAX_ENCODED];
  size_t len = 0;
  size_t mid = n / 2;
  uint16_t first = c_frame;
  CHECK_RESULT(sds_link_encode_start(&c, c_start++, msg, sizeof msg, &len), SDS_RESULT_OK);
  put(&wire, msg, len);
  for (size_t i = 0; i < n; i++) {
    if (i == mid) {
      CHECK_RESULT(sds_link_encode_frame(&frames[i], c_frame, msg, sizeof msg, &len), SDS_RESULT_OK);
      msg[len / 2] ^= (uint8_t)(msg[len / 2] == 0x01 ? 0x02 : 0x01); /* one bit, never 0x00 */
      put(&wire, msg, len);
    }
    encode_frame(&wire, &frames[i], c_frame++);
    if (i == mid + 1) encode_frame(&wire, &frames[i], (uint16_t)(c_frame - 1));
  }
  CHECK_RESULT(sds_link_encode_end((uint32_t)n, c_end++, msg, sizeof msg, &len), SDS_RESULT_OK);
  put(&wire, msg, len);
  feed(k, &wire, now_us, &answers);

  messages got = decode_all(&answers);
  size_t nev = 0, statuses = 0, summaries = 0, segments = 0, faults = 0;
  int order = 1;
  const sds_link_summary *s = NULL;
  for (size_t i = 0; i < got.len; i++) {
    const sds_link_message *g = &got.m[i];
    if (g->kind == SDS_LINK_MESSAGE_EVENT) {
      if (g->event.kind == SDS_LINK_EVENT_MONITOR) {
        if (nev >= nwant || !same_event(&g->event.monitor, &want[nev])) order = 0;
        /* Tagged with the counter of the frame that raised it. */
        if (g->event.monitor.kind == SDS_EVENT_COLLISION)
          CHECK(g->event.frame_counter == (uint16_t)(first + g->event.monitor.collision.frame));
        nev++;
      } else if (g->event.kind == SDS_LINK_EVENT_SEGMENT) {
        segments++;
        CHECK(g->event.frame_counter == first && g->event.value == 0);
      } else {
        faults++;
      }
    } else if (g->kind == SDS_LINK_MESSAGE_STATUS) {
      statuses++;
    } else if (g->kind == SDS_LINK_MESSAGE_SUMMARY) {
      summaries++;
      s = &g->summary;
    }
  }
  CHECK(order && nev == nwant);
  CHECK(segments == 1 && faults == 0 && summaries == 1);
  CHECK(statuses >= 1 + (n - 1) / 20); /* the start's answer, then one per second of frames */
  CHECK(s != NULL);
  if (s != NULL) {
    CHECK(same_summary(&s->route, &want_summary));
    CHECK(s->segments == 1 && s->gaps == 0);
    CHECK(s->counts[SDS_LINK_STATUS_OK] == n);
    CHECK(s->counts[SDS_LINK_STATUS_ERROR] == 1);
    CHECK(s->counts[SDS_LINK_STATUS_REPEATED] == 1);
    CHECK(s->counts[SDS_LINK_STATUS_OKSOMELOST] + s->counts[SDS_LINK_STATUS_WRONGSEQUENCE] +
              s->counts[SDS_LINK_STATUS_NONEWDATA] == 0);
  }
  sds_link_status st;
  CHECK_RESULT(sds_link_checker_status(k, &st), SDS_RESULT_OK);
  CHECK(st.valid && st.route == SDS_LINK_ROUTE_FINISHED && st.accepted == n);
  printf("route %s: %zu frames, %zu events equal to the monitor's, statuses OK %u ERROR %u REPEATED %u\n",
         path, n, nev, s ? s->counts[SDS_LINK_STATUS_OK] : 0, s ? s->counts[SDS_LINK_STATUS_ERROR] : 0,
         s ? s->counts[SDS_LINK_STATUS_REPEATED] : 0);
  free(got.m);
  free(wire.bytes);
  free(answers.bytes);
  free(want);
  free(frames);
}

/* A doer that stops sending: NONEWDATA at the deadline; then noise: link_fault, the pin. */
static void faults(sds_link_checker *k, uint64_t *now_us) {
  buffer wire = {NULL, 0, 0}, answers = {NULL, 0, 0};
  uint8_t msg[SDS_LINK_MAX_ENCODED];
  size_t len = 0;
  sds_config c = sds_config_default(); /* dt 0.05 s: the timeout is 3 periods, 150 ms */
  sds_frame f;
  uint64_t deadline = 0;
  memset(&f, 0, sizeof f);
  f.speed = 8.0f;
  CHECK_RESULT(sds_link_encode_start(&c, c_start++, msg, sizeof msg, &len), SDS_RESULT_OK);
  put(&wire, msg, len);
  for (int i = 0; i < 10; i++) encode_frame(&wire, &f, c_frame++);
  feed(k, &wire, now_us, &answers);
  CHECK_RESULT(sds_link_checker_deadline(k, &deadline), SDS_RESULT_OK);
  CHECK(deadline > *now_us - 1000 && deadline <= *now_us + 150000);
  /* Before the deadline nothing; at it, NONEWDATA and a status message. */
  size_t before = answers.len;
  CHECK_RESULT(sds_link_poll(k, deadline - 1, collect, &answers), SDS_RESULT_OK);
  CHECK(answers.len == before);
  CHECK_RESULT(sds_link_poll(k, deadline, collect, &answers), SDS_RESULT_OK);
  CHECK(answers.len > before);
  sds_link_status st;
  CHECK_RESULT(sds_link_checker_status(k, &st), SDS_RESULT_OK);
  CHECK(st.counts[SDS_LINK_STATUS_NONEWDATA] == 1 && st.valid);

  /* Noise: each corrupted message is ERROR; the third bad status of the window is a fault. */
  wire.len = 0;
  for (int i = 0; i < 3; i++) {
    CHECK_RESULT(sds_link_encode_frame(&f, c_frame, msg, sizeof msg, &len), SDS_RESULT_OK);
    msg[5] ^= (uint8_t)(msg[5] == 0x40 ? 0x80 : 0x40);
    put(&wire, msg, len);
  }
  feed(k, &wire, now_us, &answers);
  CHECK_RESULT(sds_link_checker_status(k, &st), SDS_RESULT_OK);
  CHECK(!st.valid && st.counts[SDS_LINK_STATUS_ERROR] == 3);
  /* A new start restores the link (a new route, a new window). */
  wire.len = 0;
  CHECK_RESULT(sds_link_encode_start(&c, c_start++, msg, sizeof msg, &len), SDS_RESULT_OK);
  put(&wire, msg, len);
  feed(k, &wire, now_us, &answers);
  CHECK_RESULT(sds_link_checker_status(k, &st), SDS_RESULT_OK);
  CHECK(st.valid && st.route == SDS_LINK_ROUTE_RUNNING);

  messages got = decode_all(&answers);
  int fault = 0, restored = 0;
  for (size_t i = 0; i < got.len; i++) {
    if (got.m[i].kind != SDS_LINK_MESSAGE_EVENT) continue;
    if (got.m[i].event.kind == SDS_LINK_EVENT_LINK_FAULT) fault += got.m[i].event.value == 3;
    if (got.m[i].event.kind == SDS_LINK_EVENT_LINK_RESTORED) restored++;
  }
  CHECK(fault == 1 && restored == 1);
  printf("faults: NONEWDATA at the deadline, link_fault after 3 bad statuses, link_restored at the next start\n");
  free(got.m);
  free(wire.bytes);
  free(answers.bytes);
}

/* Every error code the link API promises. */
static void errors(void) {
  static sds_link_checker_storage mem;
  sds_link_checker *k = (sds_link_checker *)&mem;
  sds_link_config lc = sds_link_config_default();
  sds_link_status st;
  sds_link_message m;
  uint8_t out[SDS_LINK_MAX_ENCODED];
  size_t n = 0;
  uint64_t t = 0;
  buffer sink = {NULL, 0, 0};
  sds_config c = sds_config_default();
  sds_frame f;
  memset(&f, 0, sizeof f);

  CHECK(sds_link_checker_size() <= sizeof mem);
  CHECK(lc.max_delta == 3 && lc.timeout == 3 && lc.window == 20 && lc.max_errors == 2);
  CHECK_RESULT(sds_link_checker_status(k, &st), SDS_RESULT_NOT_INITIALIZED);
  CHECK_RESULT(sds_link_checker_init(NULL, sizeof mem, &lc), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_link_checker_init(k, sizeof mem, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_link_checker_init(k, sds_link_checker_size() - 1, &lc), SDS_RESULT_BUFFER_TOO_SMALL);
  CHECK_RESULT(sds_link_checker_init((sds_link_checker *)((char *)&mem + 1), sizeof mem - 8, &lc),
               SDS_RESULT_BUFFER_MISALIGNED);
  lc.max_delta = 0;
  CHECK_RESULT(sds_link_checker_init(k, sizeof mem, &lc), SDS_RESULT_LINK_CONFIG_MAX_DELTA);
  lc = sds_link_config_default();
  lc.timeout = 0;
  CHECK_RESULT(sds_link_checker_init(k, sizeof mem, &lc), SDS_RESULT_LINK_CONFIG_TIMEOUT);
  lc = sds_link_config_default();
  lc.window = 33;
  CHECK_RESULT(sds_link_checker_init(k, sizeof mem, &lc), SDS_RESULT_LINK_CONFIG_WINDOW);
  lc = sds_link_config_default();
  lc.max_errors = 20;
  CHECK_RESULT(sds_link_checker_init(k, sizeof mem, &lc), SDS_RESULT_LINK_CONFIG_MAX_ERRORS);
  lc = sds_link_config_default();
  CHECK_RESULT(sds_link_checker_init(k, sizeof mem, &lc), SDS_RESULT_OK);
  CHECK_RESULT(sds_link_receive(k, NULL, 1, 0, collect, &sink), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_link_receive(k, NULL, 0, 0, collect, &sink), SDS_RESULT_OK);
  CHECK_RESULT(sds_link_receive(k, out, 1, 0, NULL, &sink), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_link_poll(NULL, 0, collect, &sink), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_link_checker_deadline(k, &t), SDS_RESULT_UNDEFINED); /* no route */
  CHECK_RESULT(sds_link_checker_status(k, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_link_encode_start(&c, 0, out, 10, &n), SDS_RESULT_OUTPUT_TOO_SMALL);
  CHECK_RESULT(sds_link_encode_start(&c, 0, NULL, sizeof out, &n), SDS_RESULT_NULL_POINTER);
  c.dt = -1.0f;
  CHECK_RESULT(sds_link_encode_start(&c, 0, out, sizeof out, &n), SDS_RESULT_CONFIG_DT);
  f.speed = -1.0f;
  CHECK_RESULT(sds_link_encode_frame(&f, 0, out, sizeof out, &n), SDS_RESULT_FRAME_SPEED_NEGATIVE);
  CHECK_RESULT(sds_link_encode_end(0, 0, out, sizeof out, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_link_encode_end(7, 9, out, sizeof out, &n), SDS_RESULT_OK);
  CHECK_RESULT(sds_link_decode(out, n, &m), SDS_RESULT_OK);
  CHECK(m.kind == SDS_LINK_MESSAGE_END && m.counter == 9);
  out[3] ^= 0x04;
  CHECK_RESULT(sds_link_decode(out, n, &m), SDS_RESULT_LINK_MESSAGE);
  CHECK(m.kind == 0);
  CHECK_RESULT(sds_link_decode(out, 0, &m), SDS_RESULT_LINK_MESSAGE);
  CHECK_RESULT(sds_link_decode(out, n, NULL), SDS_RESULT_NULL_POINTER);
  CHECK(strcmp(sds_result_str(SDS_RESULT_LINK_CONFIG_WINDOW), "link: window must lie in 1..=32") == 0);
}

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: test_link FRAMES.jsonl...\n");
    return 2;
  }
  errors();
  sds_link_checker *k = (sds_link_checker *)&checker_mem;
  sds_link_config lc = sds_link_config_default();
  uint64_t now_us = 0;
  CHECK_RESULT(sds_link_checker_init(k, sizeof checker_mem, &lc), SDS_RESULT_OK);
  for (int i = 1; i < argc; i++) route(k, argv[i], &now_us);
  faults(k, &now_us);
  fprintf(stderr, "c link: %u passed, %u failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
