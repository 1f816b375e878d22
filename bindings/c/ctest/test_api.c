/*
 * test_api.c: the C API from C99 (gcc -std=c99 -Wall -Wextra -Werror, linked statically
 * against libsds_monitor.a, run under valgrind).
 *
 *   test_api [FRAMES.jsonl...]
 *
 * Checks every error path the API promises (NULLs, a too-small or misaligned buffer, a never
 * initialised monitor, each invalid configuration field, each invalid frame field, a frame
 * after finish) and the monitor's verdicts on a made-up route, then replays the frames files
 * given (stdout: the lines `monitor_replay` prints, compared byte for byte by run-tests.sh).
 * The closing line on stderr is "c api: N passed, M failed"; the exit status is 1 on a failure.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "replay_file.h"
#include "sds_monitor.h"

static sds_monitor_storage storage;

static sds_monitor *fresh(void) {
  sds_monitor *m = (sds_monitor *)&storage;
  sds_config c = sds_config_default();
  CHECK_RESULT(sds_monitor_init(m, sizeof storage, &c), SDS_RESULT_OK);
  return m;
}

static sds_frame cruise(void) {
  sds_frame f;
  memset(&f, 0, sizeof f);
  f.speed = 8.0f;
  f.lat_err = 0.1f;
  f.has_lat_err = true;
  return f;
}

static void test_sizes(void) {
  CHECK(sds_monitor_size() > 0);
  CHECK(sds_monitor_size() <= sizeof(sds_monitor_storage));
  CHECK(sds_monitor_align() > 0 && sds_monitor_align() <= 8);
  CHECK((sds_monitor_align() & (sds_monitor_align() - 1)) == 0);
}

static void test_nulls(void) {
  sds_monitor *m = fresh();
  sds_config c = sds_config_default();
  sds_frame f = cruise();
  sds_events ev;
  sds_summary s;
  sds_record_scores rec;
  sds_safe_score safe;
  double score;
  char buf[SDS_NUMBER_TEXT_MAX];
  size_t n;
  float v2[2] = {1.0f, 0.0f};

  memset(&rec, 0, sizeof rec);
  memset(&s, 0, sizeof s);
  CHECK_RESULT(sds_monitor_init(NULL, sizeof storage, &c), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_init(m, sizeof storage, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_push(NULL, &f, &ev), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_push(m, NULL, &ev), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_push(m, &f, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_finish(NULL, &ev, &s), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_finish(m, NULL, &s), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_finish(m, &ev, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_reset(NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_summary(NULL, &s), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_summary(m, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_config(NULL, &c), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_monitor_config(m, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_config_validate(NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_frame_from_vectors(NULL, v2, v2, 0.0f, 0.0f, &f), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_frame_from_vectors(v2, NULL, v2, 0.0f, 0.0f, &f), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_frame_from_vectors(v2, v2, NULL, 0.0f, 0.0f, &f), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_frame_from_vectors(v2, v2, v2, 0.0f, 0.0f, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_format_f32(1.0f, NULL, sizeof buf, &n), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_format_f32(1.0f, buf, sizeof buf, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_format_f64(1.0, NULL, sizeof buf, &n), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_summary_comfort_score(NULL, &score), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_summary_comfort_score(&s, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_ds_safe(NULL, &rec, &c.factors, &safe), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_ds_safe(&s, NULL, &c.factors, &safe), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_ds_safe(&s, &rec, NULL, &safe), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_ds_safe(&s, &rec, &c.factors, NULL), SDS_RESULT_NULL_POINTER);
  /* The NULL calls changed nothing: the monitor still has no frame. */
  CHECK_RESULT(sds_monitor_summary(m, &s), SDS_RESULT_OK);
  CHECK(s.frames == 0);
}

static void test_buffer(void) {
  static sds_monitor_storage zeroed;  /* all zero: never initialised */
  static sds_monitor_storage big[2];
  sds_config c = sds_config_default();
  sds_frame f = cruise();
  sds_events ev;
  sds_monitor *m = (sds_monitor *)&big[0];
  sds_monitor *odd = (sds_monitor *)((unsigned char *)&big[0] + 1);

  CHECK_RESULT(sds_monitor_push((sds_monitor *)&zeroed, &f, &ev), SDS_RESULT_NOT_INITIALIZED);
  CHECK_RESULT(sds_monitor_reset((sds_monitor *)&zeroed), SDS_RESULT_NOT_INITIALIZED);
  CHECK_RESULT(sds_monitor_init(m, 0, &c), SDS_RESULT_BUFFER_TOO_SMALL);
  CHECK_RESULT(sds_monitor_init(m, sds_monitor_size() - 1, &c), SDS_RESULT_BUFFER_TOO_SMALL);
  if (sds_monitor_align() > 1) {
    CHECK_RESULT(sds_monitor_init(odd, sds_monitor_size(), &c), SDS_RESULT_BUFFER_MISALIGNED);
    CHECK_RESULT(sds_monitor_push(odd, &f, &ev), SDS_RESULT_BUFFER_MISALIGNED);
  }
  /* Misaligned argument pointers (a struct cast from a byte buffer) are refused too. */
  CHECK_RESULT(sds_monitor_push((sds_monitor *)&zeroed, (const sds_frame *)((char *)&f + 1), &ev),
               SDS_RESULT_MISALIGNED_POINTER);
  CHECK_RESULT(sds_monitor_push((sds_monitor *)&zeroed, &f, (sds_events *)((char *)&big[1] + 2)),
               SDS_RESULT_MISALIGNED_POINTER);
  CHECK_RESULT(sds_config_validate((const sds_config *)((char *)&c + 2)),
               SDS_RESULT_MISALIGNED_POINTER);
  /* A failed init leaves the buffer untouched. */
  CHECK(memcmp(&big[0], &zeroed, sizeof zeroed) == 0);
  CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_NOT_INITIALIZED);
  /* Exactly sds_monitor_size() bytes are enough. */
  CHECK_RESULT(sds_monitor_init(m, sds_monitor_size(), &c), SDS_RESULT_OK);
  CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_OK);
}

/* Sets one field wrong, expects its code from both validate and init. */
#define BAD_CONFIG(stmt, want)                                                 \
  do {                                                                         \
    sds_config c_ = sds_config_default();                                      \
    sds_config *c = &c_;                                                       \
    stmt;                                                                      \
    CHECK_RESULT(sds_config_validate(c), want);                                \
    CHECK_RESULT(sds_monitor_init(m, sizeof storage, c), want);                \
  } while (0)

static void test_config(void) {
  sds_config c = sds_config_default();
  sds_config back;
  sds_monitor *m = fresh();
  sds_summary s;
  sds_frame f = cruise();
  sds_events ev;

  /* The defaults are the spec's. */
  CHECK(c.profile == SDS_PROFILE_PHYSICAL);
  CHECK(c.dt == 0.05f && c.chunk_len == 20 && c.min_chunk == 7 && c.decel_window == 20);
  CHECK(c.bounds.lon_acc_min == -4.05f && c.bounds.yaw_rate == 0.95f);
  CHECK(c.slack == 0.82f && c.anomalous_excess == 0.25f && c.critical_excess == 0.65f);
  CHECK(c.factors.workzone == 0.5 && c.factors.layout == 0.65 && c.factors.nodecel == 0.8);
  CHECK_RESULT(sds_config_validate(&c), SDS_RESULT_OK);

  CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_OK);
  BAD_CONFIG(c->profile = 3, SDS_RESULT_CONFIG_PROFILE);
  BAD_CONFIG(c->dt = 0.0f, SDS_RESULT_CONFIG_DT);
  BAD_CONFIG(c->dt = NAN, SDS_RESULT_CONFIG_DT);
  BAD_CONFIG(c->legacy_jerk_spacing = -0.1f, SDS_RESULT_CONFIG_LEGACY_SPACING);
  BAD_CONFIG(c->min_chunk = 6, SDS_RESULT_CONFIG_MIN_CHUNK);
  BAD_CONFIG(c->chunk_len = SDS_CAPACITY + 1, SDS_RESULT_CONFIG_CHUNK_LEN);
  BAD_CONFIG((c->min_chunk = 10, c->chunk_len = 9), SDS_RESULT_CONFIG_CHUNK_LEN);
  BAD_CONFIG(c->decel_window = SDS_CAPACITY + 1, SDS_RESULT_CONFIG_DECEL_WINDOW);
  BAD_CONFIG(c->bounds.lon_acc_min = c->bounds.lon_acc_max, SDS_RESULT_CONFIG_BOUNDS);
  BAD_CONFIG(c->bounds.yaw_acc = 0.0f, SDS_RESULT_CONFIG_BOUNDS);
  BAD_CONFIG(c->bounds.lat_acc = INFINITY, SDS_RESULT_CONFIG_BOUNDS);
  BAD_CONFIG(c->slack = -0.01f, SDS_RESULT_CONFIG_SLACK);
  BAD_CONFIG(c->anomalous_excess = 0.7f, SDS_RESULT_CONFIG_EXCESS_BANDS);
  BAD_CONFIG(c->decel_threshold = -INFINITY, SDS_RESULT_CONFIG_DECEL_THRESHOLD);
  BAD_CONFIG(c->stationary_speed = -1.0f, SDS_RESULT_CONFIG_STATIONARY_SPEED);
  BAD_CONFIG(c->factors.critical = 1.5, SDS_RESULT_CONFIG_FACTOR);
  BAD_CONFIG(c->factors.layout = 0.0, SDS_RESULT_CONFIG_FACTOR);
  BAD_CONFIG(c->factors.nodecel = NAN, SDS_RESULT_CONFIG_FACTOR);
  /* The core refuses a monitor capacity over 1024 frames. The C monitor's capacity is fixed
   * (SDS_CAPACITY, 20, checked against that bound when the library is built), so no call can
   * return it: the code is part of the ABI with its own text, and fields at their largest
   * still give their own codes. */
  CHECK(SDS_RESULT_CONFIG_CAPACITY == 112);
  CHECK(strcmp(sds_result_str(SDS_RESULT_CONFIG_CAPACITY),
               "config: the monitor capacity must be at most 1024 frames") == 0);
  CHECK(SDS_CAPACITY <= 1024);
  BAD_CONFIG(c->chunk_len = 0xFFFF, SDS_RESULT_CONFIG_CHUNK_LEN);
  BAD_CONFIG(c->decel_window = 0xFFFF, SDS_RESULT_CONFIG_DECEL_WINDOW);
  /* The refused re-inits left the running monitor as it was. */
  CHECK_RESULT(sds_monitor_summary(m, &s), SDS_RESULT_OK);
  CHECK(s.frames == 1);

  /* Issue 47 item 11: Autoware's profile with the physical bounds is refused (it judged a
   * +-1.8 m/s2 drive 20/20 comfortable where `sds --profile autoware` says 0/20). */
  BAD_CONFIG(c->profile = SDS_PROFILE_AUTOWARE, SDS_RESULT_CONFIG_PROFILE_BOUNDS);
  CHECK(SDS_RESULT_CONFIG_PROFILE_BOUNDS == 113);
  CHECK_RESULT(sds_config_profile(SDS_PROFILE_AUTOWARE, NULL), SDS_RESULT_NULL_POINTER);
  CHECK_RESULT(sds_config_profile(3, &back), SDS_RESULT_CONFIG_PROFILE);
  CHECK_RESULT(sds_monitor_summary(m, &s), SDS_RESULT_OK);
  CHECK(s.frames == 1);

  /* A valid non-default configuration is taken and read back field by field. */
  c.profile = SDS_PROFILE_B2D_LEGACY;
  c.chunk_len = 10;
  c.decel_window = 5;
  c.factors.critical = 0.5;
  CHECK_RESULT(sds_monitor_init(m, sizeof storage, &c), SDS_RESULT_OK);
  CHECK_RESULT(sds_monitor_config(m, &back), SDS_RESULT_OK);
  CHECK(back.profile == SDS_PROFILE_B2D_LEGACY && back.chunk_len == 10 &&
        back.decel_window == 5 && back.factors.critical == 0.5);
}

/* Issue 47 item 11: a 1.8 m/s2 drive (a 20-frame chunk) under each profile's bounds, from
 * sds_config_profile: comfortable under the physical bounds, not under Autoware's (|a_lon| >
 * 1.0), as `sds --profile autoware` judges it. */
static unsigned comfortable_chunks(sds_profile profile) {
  sds_config c;
  sds_monitor *m = (sds_monitor *)&storage;
  sds_events ev;
  sds_summary s;
  unsigned i;
  CHECK_RESULT(sds_config_profile(profile, &c), SDS_RESULT_OK);
  CHECK(c.profile == profile);
  CHECK_RESULT(sds_monitor_init(m, sizeof storage, &c), SDS_RESULT_OK);
  for (i = 0; i < 20; i++) {
    sds_frame f = cruise();
    f.a_lon = 1.8f;
    f.a_mag = 1.8f;
    CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_OK);
  }
  CHECK_RESULT(sds_monitor_finish(m, &ev, &s), SDS_RESULT_OK);
  CHECK(s.comfort.chunks == 1);
  return s.comfort.comfortable;
}

static void test_profiles(void) {
  sds_config c;
  CHECK_RESULT(sds_config_profile(SDS_PROFILE_AUTOWARE, &c), SDS_RESULT_OK);
  CHECK(c.bounds.lon_acc_min == -1.0f && c.bounds.lon_acc_max == 1.0f && c.bounds.lat_acc == 1.0f);
  CHECK(c.bounds.mag_jerk == 1.0f && c.bounds.lon_jerk == 1.0f && c.bounds.yaw_rate == 0.95f);
  CHECK(c.dt == 0.05f && c.chunk_len == 20 && c.slack == 0.82f);
  CHECK_RESULT(sds_config_validate(&c), SDS_RESULT_OK);
  CHECK_RESULT(sds_config_profile(SDS_PROFILE_PHYSICAL, &c), SDS_RESULT_OK);
  CHECK(c.bounds.lon_acc_max == 2.40f);
  CHECK(comfortable_chunks(SDS_PROFILE_PHYSICAL) == 1);
  CHECK(comfortable_chunks(SDS_PROFILE_AUTOWARE) == 0);
}

/* Pushes one frame with field `field` set to `value`; expects `want` and no change. */
#define BAD_FRAME(stmt, want)                                  \
  do {                                                         \
    sds_frame f_ = cruise();                                   \
    sds_frame *f = &f_;                                        \
    stmt;                                                      \
    CHECK_RESULT(sds_monitor_push(m, f, &ev), want);           \
    CHECK(ev.len == 0);                                        \
  } while (0)

static void test_frames(void) {
  sds_monitor *m = fresh();
  sds_events ev;
  sds_summary s;
  sds_frame ok = cruise();

  CHECK_RESULT(sds_monitor_push(m, &ok, &ev), SDS_RESULT_OK);
  BAD_FRAME(f->a_lon = NAN, SDS_RESULT_FRAME_A_LON_NOT_FINITE);
  BAD_FRAME(f->a_lat = INFINITY, SDS_RESULT_FRAME_A_LAT_NOT_FINITE);
  BAD_FRAME(f->a_mag = NAN, SDS_RESULT_FRAME_A_MAG_NOT_FINITE);
  BAD_FRAME(f->yaw_rate = -INFINITY, SDS_RESULT_FRAME_YAW_RATE_NOT_FINITE);
  BAD_FRAME(f->speed = NAN, SDS_RESULT_FRAME_SPEED_NOT_FINITE);
  BAD_FRAME(f->lat_err = NAN, SDS_RESULT_FRAME_LAT_ERR_NOT_FINITE);
  BAD_FRAME(f->speed = -1.0f, SDS_RESULT_FRAME_SPEED_NEGATIVE);
  BAD_FRAME(f->a_mag = -0.5f, SDS_RESULT_FRAME_A_MAG_NEGATIVE);
  /* A NaN lat_err is ignored when it is marked unknown. */
  BAD_FRAME((f->lat_err = NAN, f->has_lat_err = false), SDS_RESULT_OK);
  /* Only the two good frames counted. */
  CHECK_RESULT(sds_monitor_summary(m, &s), SDS_RESULT_OK);
  CHECK(s.frames == 2);

  /* After finish: no frame, no second finish, until reset. */
  CHECK_RESULT(sds_monitor_finish(m, &ev, &s), SDS_RESULT_OK);
  CHECK(s.frames == 2);
  CHECK_RESULT(sds_monitor_push(m, &ok, &ev), SDS_RESULT_FINISHED);
  CHECK(ev.len == 0);
  CHECK_RESULT(sds_monitor_finish(m, &ev, &s), SDS_RESULT_FINISHED);
  CHECK_RESULT(sds_monitor_reset(m), SDS_RESULT_OK);
  CHECK_RESULT(sds_monitor_push(m, &ok, &ev), SDS_RESULT_OK);
  CHECK_RESULT(sds_monitor_summary(m, &s), SDS_RESULT_OK);
  CHECK(s.frames == 1);
}

/* The Rust doc example's route: 30 cruise frames, then a hit at speed without braking. */
static void test_verdicts(void) {
  sds_monitor *m = fresh();
  sds_events ev;
  sds_summary s;
  sds_frame f = cruise();
  double score = 0.0;
  unsigned comfort_events = 0;

  for (int i = 0; i < 30; i++) {
    CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_OK);
    comfort_events += ev.len;
    if (ev.len == 1) {
      CHECK(i == 19); /* the first chunk ends at frame 19 */
      CHECK(ev.events[0].kind == SDS_EVENT_COMFORT);
      CHECK(ev.events[0].comfort.chunk == 0 && ev.events[0].comfort.frames == 20);
      CHECK(ev.events[0].comfort.comfortable);
    }
  }
  CHECK(comfort_events == 1);
  f.collisions.vehicle = 1;
  CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_OK);
  CHECK(ev.len == 1);
  CHECK(ev.events[0].kind == SDS_EVENT_COLLISION);
  CHECK(ev.events[0].collision.frame == 30);
  CHECK(ev.events[0].collision.collisions.vehicle == 1);
  CHECK(ev.events[0].collision.speed == 8.0f);
  CHECK(!ev.events[0].collision.decelerated && !ev.events[0].collision.exempt);
  CHECK(ev.events[0].collision.nodecel);
  CHECK(ev.events[1].kind == SDS_EVENT_NONE);
  CHECK_RESULT(sds_monitor_finish(m, &ev, &s), SDS_RESULT_OK);
  CHECK(s.frames == 31);
  CHECK(s.collisions.aligned == 1 && s.collisions.nodecel == 1 && s.collisions.exempt == 0);
  CHECK(s.comfort.chunks == 1 && s.comfort.comfortable == 1); /* trailing 11 frames dropped */
  CHECK(s.lateral.chunks == 2 && s.lateral.scored_chunks == 2); /* ... counted for lateral */
  CHECK_RESULT(sds_summary_comfort_score(&s, &score), SDS_RESULT_OK);
  CHECK(score == 1.0);

  /* A critical lateral excess: lat_err - slack = 1.0 m > 0.65 m, at the chunk's end. */
  CHECK_RESULT(sds_monitor_reset(m), SDS_RESULT_OK);
  f = cruise();
  f.lat_err = 1.82f;
  for (int i = 0; i < 20; i++) {
    CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_OK);
  }
  CHECK(ev.len == 2 && ev.events[0].kind == SDS_EVENT_COMFORT);
  CHECK(ev.events[1].kind == SDS_EVENT_LATERAL && ev.events[1].lateral.chunk == 0);
  CHECK(ev.events[1].lateral.band == SDS_BAND_CRITICAL);
  CHECK(fabsf(ev.events[1].lateral.max_excess - 1.0f) < 1e-6f);

  /* Six frames: no comfort chunk, the score is undefined. */
  CHECK_RESULT(sds_monitor_reset(m), SDS_RESULT_OK);
  f = cruise();
  for (int i = 0; i < 6; i++) {
    CHECK_RESULT(sds_monitor_push(m, &f, &ev), SDS_RESULT_OK);
  }
  CHECK_RESULT(sds_monitor_finish(m, &ev, &s), SDS_RESULT_OK);
  CHECK(s.comfort.chunks == 0 && s.lateral.chunks == 1);
  CHECK_RESULT(sds_summary_comfort_score(&s, &score), SDS_RESULT_UNDEFINED);
  CHECK(isnan(score));
}

/* Field by field (padding bytes are unspecified, so no memcmp of events). */
static int same_events(const sds_events *a, const sds_events *b) {
  if (a->len != b->len) {
    return 0;
  }
  for (uint32_t i = 0; i < a->len; i++) {
    const sds_event *x = &a->events[i], *y = &b->events[i];
    if (x->kind != y->kind || x->collision.frame != y->collision.frame ||
        x->collision.speed != y->collision.speed ||
        x->collision.decelerated != y->collision.decelerated ||
        x->collision.nodecel != y->collision.nodecel || x->comfort.chunk != y->comfort.chunk ||
        x->comfort.comfortable != y->comfort.comfortable || x->lateral.chunk != y->lateral.chunk ||
        x->lateral.max_excess != y->lateral.max_excess) {
      return 0;
    }
  }
  return 1;
}

/* A monitor holds no pointers: a memcpy is an independent snapshot that goes on identically. */
static void test_snapshot(void) {
  static sds_monitor_storage copy;
  sds_monitor *m = fresh();
  sds_monitor *c = (sds_monitor *)&copy;
  sds_events ev_m, ev_c;
  sds_summary s_m, s_c;
  sds_frame f = cruise();
  for (int i = 0; i < 25; i++) {
    f.a_lon = (float)(i % 7) * -0.9f;
    CHECK_RESULT(sds_monitor_push(m, &f, &ev_m), SDS_RESULT_OK);
  }
  memcpy(&copy, &storage, sizeof copy);
  f.collisions.vehicle = 1;
  CHECK_RESULT(sds_monitor_push(m, &f, &ev_m), SDS_RESULT_OK);
  CHECK_RESULT(sds_monitor_push(c, &f, &ev_c), SDS_RESULT_OK);
  CHECK(ev_m.len == 1 && ev_m.events[0].kind == SDS_EVENT_COLLISION);
  CHECK(ev_m.events[0].collision.decelerated); /* a_lon -4.5 .. -0.9 within the window */
  CHECK(same_events(&ev_m, &ev_c));
  CHECK_RESULT(sds_monitor_finish(m, &ev_m, &s_m), SDS_RESULT_OK);
  CHECK_RESULT(sds_monitor_finish(c, &ev_c, &s_c), SDS_RESULT_OK);
  CHECK(s_m.frames == 26 && memcmp(&s_m, &s_c, sizeof s_m) == 0);
  CHECK(same_events(&ev_m, &ev_c));
  /* The original was untouched by the copy's pushes: a reset one and the copy are independent. */
  CHECK_RESULT(sds_monitor_reset(m), SDS_RESULT_OK);
  CHECK_RESULT(sds_monitor_push(c, &f, &ev_c), SDS_RESULT_FINISHED);
}

static void test_scores_and_text(void) {
  sds_summary s;
  sds_record_scores rec;
  sds_safe_score safe;
  sds_config c = sds_config_default();
  char buf[SDS_NUMBER_TEXT_MAX];
  size_t n = 0;
  double p;
  sds_frame f;
  float acc[2] = {1.5f, -0.25f}, fwd[2] = {0.6f, 0.8f}, right[2] = {0.8f, -0.6f};

  memset(&s, 0, sizeof s);
  s.collisions.nodecel = 1;
  rec.score_route = 100.0;
  rec.score_penalty = 0.65;
  rec.workzone = 1;
  CHECK_RESULT(sds_ds_safe(&s, &rec, &c.factors, &safe), SDS_RESULT_OK);
  /* The spec's product, left to right: the same operations give the same bits. */
  p = 0.65 * (0.5 / 0.65);
  CHECK(safe.p_safe == p);
  CHECK(safe.ds_safe == 100.0 * p * 0.8);

  CHECK_RESULT(sds_format_f32(0.5f, buf, sizeof buf, &n), SDS_RESULT_OK);
  CHECK(n == 3 && strcmp(buf, "0.5") == 0);
  CHECK_RESULT(sds_format_f32(2.68f, buf, sizeof buf, &n), SDS_RESULT_OK);
  CHECK(strcmp(buf, "2.68") == 0);
  CHECK_RESULT(sds_format_f32(1.0f, buf, sizeof buf, &n), SDS_RESULT_OK);
  CHECK(strcmp(buf, "1.0") == 0);
  CHECK_RESULT(sds_format_f32(0.5f, buf, 3, &n), SDS_RESULT_OUTPUT_TOO_SMALL);
  CHECK_RESULT(sds_format_f64(0.1, buf, sizeof buf, &n), SDS_RESULT_OK);
  CHECK(strcmp(buf, "0.1") == 0);

  memset(&f, 0, sizeof f);
  f.has_lat_err = true;
  f.lat_err = 0.25f;
  CHECK_RESULT(sds_frame_from_vectors(acc, fwd, right, 3.0f, 7.0f, &f), SDS_RESULT_OK);
  CHECK(f.a_lon == 1.5f * 0.6f + -0.25f * 0.8f);
  CHECK(f.a_lat == 1.5f * 0.8f + -0.25f * -0.6f);
  CHECK(f.yaw_rate == 3.0f && f.speed == 7.0f && f.has_lat_err && f.lat_err == 0.25f);

  CHECK(strcmp(sds_result_str(SDS_RESULT_OK), "ok") == 0);
  CHECK(strcmp(sds_result_str(12345), "unknown result code") == 0);
  CHECK(strcmp(sds_result_str(SDS_RESULT_FRAME_SPEED_NOT_FINITE),
               sds_result_str(SDS_RESULT_FRAME_A_LON_NOT_FINITE)) != 0);
}

int main(int argc, char **argv) {
  int replayed = 1;
  test_sizes();
  test_nulls();
  test_buffer();
  test_config();
  test_profiles();
  test_frames();
  test_verdicts();
  test_snapshot();
  test_scores_and_text();
  for (int i = 1; i < argc && replayed; i++) {
    replayed = sds_replay_file((uint32_t)(i - 1), argv[i]);
  }
  CHECK(replayed);
  CHECK(fflush(stdout) == 0);
  fprintf(stderr, "c api: %u passed, %u failed\n", passed, failed);
  return failed == 0 ? 0 : 1;
}
