/* sds_lines.c: see sds_lines.h. */
#include "sds_lines.h"

/* A bounded text buffer: a failed put marks it and writes nothing more. */
typedef struct text {
  char *buf;
  size_t cap;
  size_t len;
  bool ok;
} text;

static text text_new(char *out, size_t cap) {
  text t;
  t.buf = out;
  t.cap = cap;
  t.len = 0;
  t.ok = out != NULL && cap > 0;
  if (t.ok) {
    out[0] = '\0';
  }
  return t;
}

static void put(text *t, const char *s) {
  size_t n = 0;
  if (!t->ok) {
    return;
  }
  while (s[n] != '\0') {
    n++;
  }
  if (n >= t->cap - t->len) {
    t->ok = false;
    return;
  }
  for (size_t i = 0; i < n; i++) {
    t->buf[t->len + i] = s[i];
  }
  t->len += n;
  t->buf[t->len] = '\0';
}

static void put_u32(text *t, uint32_t v) {
  char digits[11];
  int i = 10;
  digits[10] = '\0';
  do {
    digits[--i] = (char)('0' + v % 10u);
    v /= 10u;
  } while (v != 0u);
  put(t, digits + i);
}

static void put_bool(text *t, bool b) { put(t, b ? "true" : "false"); }

/* As serde-json-core: the shortest round-trip form; null when not finite. */
static void put_f32(text *t, float v) {
  char digits[SDS_NUMBER_TEXT_MAX];
  size_t n = 0;
  if (v - v != 0.0f) { /* NaN or infinite */
    put(t, "null");
    return;
  }
  if (sds_format_f32(v, digits, sizeof digits, &n) != SDS_RESULT_OK) {
    t->ok = false;
    return;
  }
  put(t, digits);
}

/* ,"NAME":N  (or {"NAME":N when first) */
static void field_u32(text *t, const char *sep, const char *name, uint32_t v) {
  put(t, sep);
  put(t, "\"");
  put(t, name);
  put(t, "\":");
  put_u32(t, v);
}

static void field_bool(text *t, const char *sep, const char *name, bool v) {
  put(t, sep);
  put(t, "\"");
  put(t, name);
  put(t, "\":");
  put_bool(t, v);
}

static size_t finish(text *t) {
  put(t, "\n");
  return t->ok ? t->len : 0;
}

void sds_pins_see(sds_pins *pins, const sds_event *e) {
  bool alarm = false;
  switch (e->kind) {
    case SDS_EVENT_COLLISION:
      alarm = e->collision.nodecel;
      break;
    case SDS_EVENT_LATERAL:
      alarm = e->lateral.band == SDS_BAND_CRITICAL;
      break;
    case SDS_EVENT_COMFORT:
      if (!e->comfort.comfortable && !pins->comfort) {
        pins->comfort_rises++;
      }
      pins->comfort = !e->comfort.comfortable;
      break;
    default:
      break;
  }
  if (alarm && !pins->alarm) {
    pins->alarm = true;
    pins->alarm_rises++;
  }
}

size_t sds_line_event(char *out, size_t cap, const sds_event *e) {
  text t = text_new(out, cap);
  put(&t, "event ");
  switch (e->kind) {
    case SDS_EVENT_COLLISION: {
      const sds_collision_verdict *v = &e->collision;
      field_u32(&t, "{\"collision\":{", "frame", v->frame);
      field_u32(&t, ",\"collisions\":{", "pedestrian", v->collisions.pedestrian);
      field_u32(&t, ",", "vehicle", v->collisions.vehicle);
      field_u32(&t, ",", "layout", v->collisions.layout);
      field_u32(&t, ",", "workzone", v->collisions.workzone);
      put(&t, "},\"speed\":");
      put_f32(&t, v->speed);
      field_bool(&t, ",", "decelerated", v->decelerated);
      field_bool(&t, ",", "exempt", v->exempt);
      put(&t, "}}");
      break;
    }
    case SDS_EVENT_COMFORT: {
      const sds_comfort_verdict *v = &e->comfort;
      field_u32(&t, "{\"comfort\":{", "chunk", v->chunk);
      field_u32(&t, ",", "frames", v->frames);
      field_bool(&t, ",\"failed\":{", "lon_acc", v->failed.lon_acc);
      field_bool(&t, ",", "lat_acc", v->failed.lat_acc);
      field_bool(&t, ",", "mag_jerk", v->failed.mag_jerk);
      field_bool(&t, ",", "lon_jerk", v->failed.lon_jerk);
      field_bool(&t, ",", "yaw_acc", v->failed.yaw_acc);
      field_bool(&t, ",", "yaw_rate", v->failed.yaw_rate);
      put(&t, "}}}");
      break;
    }
    case SDS_EVENT_LATERAL: {
      const sds_lateral_verdict *v = &e->lateral;
      field_u32(&t, "{\"lateral\":{", "chunk", v->chunk);
      put(&t, ",\"max_excess\":");
      put_f32(&t, v->max_excess);
      put(&t, ",\"band\":");
      switch (v->band) {
        case SDS_BAND_NORMAL:
          put(&t, "\"normal\"");
          break;
        case SDS_BAND_ANOMALOUS:
          put(&t, "\"anomalous\"");
          break;
        case SDS_BAND_CRITICAL:
          put(&t, "\"critical\"");
          break;
        default:
          t.ok = false;
          break;
      }
      put(&t, "}}");
      break;
    }
    default:
      t.ok = false;
      break;
  }
  return finish(&t);
}

size_t sds_line_summary(char *out, size_t cap, const sds_summary *s) {
  text t = text_new(out, cap);
  const sds_failure_counts *f = &s->comfort.failed;
  put(&t, "summary ");
  field_u32(&t, "{", "frames", s->frames);
  field_u32(&t, ",\"comfort\":{", "chunks", s->comfort.chunks);
  field_u32(&t, ",", "comfortable", s->comfort.comfortable);
  field_u32(&t, ",\"failed\":{", "lon_acc", f->lon_acc);
  field_u32(&t, ",", "lat_acc", f->lat_acc);
  field_u32(&t, ",", "mag_jerk", f->mag_jerk);
  field_u32(&t, ",", "lon_jerk", f->lon_jerk);
  field_u32(&t, ",", "yaw_acc", f->yaw_acc);
  field_u32(&t, ",", "yaw_rate", f->yaw_rate);
  field_u32(&t, "}},\"lateral\":{", "chunks", s->lateral.chunks);
  field_u32(&t, ",", "scored_chunks", s->lateral.scored_chunks);
  field_u32(&t, ",", "anomalous", s->lateral.anomalous);
  field_u32(&t, ",", "critical", s->lateral.critical);
  field_u32(&t, "},\"collisions\":{", "aligned", s->collisions.aligned);
  field_u32(&t, ",", "exempt", s->collisions.exempt);
  field_u32(&t, ",", "nodecel", s->collisions.nodecel);
  put(&t, "}}");
  return finish(&t);
}

size_t sds_line_pins(char *out, size_t cap, const sds_pins *p) {
  text t = text_new(out, cap);
  put(&t, "pins ");
  field_bool(&t, "{", "alarm", p->alarm);
  field_u32(&t, ",", "alarm_rises", p->alarm_rises);
  field_bool(&t, ",", "comfort", p->comfort);
  field_u32(&t, ",", "comfort_rises", p->comfort_rises);
  put(&t, "}");
  return finish(&t);
}

size_t sds_line_u32(char *out, size_t cap, const char *name, uint32_t n) {
  text t = text_new(out, cap);
  put(&t, name);
  put(&t, " ");
  put_u32(&t, n);
  return finish(&t);
}
