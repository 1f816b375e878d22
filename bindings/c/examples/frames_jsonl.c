/* frames_jsonl.c: see frames_jsonl.h. */
#include "frames_jsonl.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *skip_ws(const char *p) {
  while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') {
    p++;
  }
  return p;
}

/* Reads "KEY" into key (at most cap-1 chars); returns the position after it, or NULL. */
static const char *read_key(const char *p, char *key, size_t cap) {
  size_t n = 0;
  if (*p != '"') {
    return NULL;
  }
  p++;
  while (*p != '"') {
    if (*p == '\0' || *p == '\\' || n + 1 >= cap) {
      return NULL;
    }
    key[n++] = *p++;
  }
  key[n] = '\0';
  return p + 1;
}

static const char *read_f32(const char *p, float *out) {
  char *end = NULL;
  /* JSON numbers only: strtof would also take "nan", "inf" and hex floats. */
  if (*p != '-' && (*p < '0' || *p > '9')) {
    return NULL;
  }
  errno = 0;
  *out = strtof(p, &end);
  /* ERANGE on overflow is an error; on underflow the (subnormal or zero) result is right. */
  if (end == p || (errno == ERANGE && (*out == HUGE_VALF || *out == -HUGE_VALF))) {
    return NULL;
  }
  return end;
}

static const char *read_u16(const char *p, uint16_t *out) {
  char *end = NULL;
  unsigned long v;
  if (*p < '0' || *p > '9') {
    return NULL;
  }
  errno = 0;
  v = strtoul(p, &end, 10);
  if (end == p || errno == ERANGE || v > 65535ul) {
    return NULL;
  }
  *out = (uint16_t)v;
  return end;
}

static const char *read_collisions(const char *p, sds_collisions *c) {
  char key[32];
  p = skip_ws(p);
  if (*p != '{') {
    return NULL;
  }
  p = skip_ws(p + 1);
  if (*p == '}') {
    return p + 1;
  }
  for (;;) {
    uint16_t *slot;
    p = read_key(skip_ws(p), key, sizeof key);
    if (p == NULL) {
      return NULL;
    }
    p = skip_ws(p);
    if (*p != ':') {
      return NULL;
    }
    p = skip_ws(p + 1);
    if (strcmp(key, "pedestrian") == 0) {
      slot = &c->pedestrian;
    } else if (strcmp(key, "vehicle") == 0) {
      slot = &c->vehicle;
    } else if (strcmp(key, "layout") == 0) {
      slot = &c->layout;
    } else if (strcmp(key, "workzone") == 0) {
      slot = &c->workzone;
    } else {
      return NULL;
    }
    p = read_u16(p, slot);
    if (p == NULL) {
      return NULL;
    }
    p = skip_ws(p);
    if (*p == '}') {
      return p + 1;
    }
    if (*p != ',') {
      return NULL;
    }
    p++;
  }
}

/* Skips one JSON value (the "host" object `sds frames` adds: values the host computed, which the
   monitor does not take); returns the position after it, or NULL. Nesting is bounded. */
static const char *skip_value(const char *p, int depth) {
  p = skip_ws(p);
  if (depth > 8) {
    return NULL;
  }
  if (*p == '"') {
    for (p++; *p != '"'; p++) {
      if (*p == '\0') {
        return NULL;
      }
      if (*p == '\\' && p[1] != '\0') {
        p++;
      }
    }
    return p + 1;
  }
  if (*p == '{' || *p == '[') {
    char close = *p == '{' ? '}' : ']';
    p = skip_ws(p + 1);
    if (*p == close) {
      return p + 1;
    }
    for (;;) {
      if (close == '}') {
        p = skip_value(p, depth + 1); /* the key */
        if (p == NULL || *(p = skip_ws(p)) != ':') {
          return NULL;
        }
        p++;
      }
      p = skip_value(p, depth + 1);
      if (p == NULL) {
        return NULL;
      }
      p = skip_ws(p);
      if (*p == close) {
        return p + 1;
      }
      if (*p != ',') {
        return NULL;
      }
      p++;
    }
  }
  /* A number, true, false or null. */
  if (!((*p >= '0' && *p <= '9') || *p == '-' || *p == 't' || *p == 'f' || *p == 'n')) {
    return NULL;
  }
  while (*p != '\0' && *p != ',' && *p != '}' && *p != ']' && *p != ' ' && *p != '\n') {
    p++;
  }
  return p;
}

const char *sds_frame_parse_json(const char *line, sds_frame *frame) {
  char key[32];
  const char *p = skip_ws(line);
  memset(frame, 0, sizeof *frame);
  if (*p != '{') {
    return "not a JSON object";
  }
  p = skip_ws(p + 1);
  if (*p == '}') {
    return "empty frame";
  }
  for (;;) {
    float *slot = NULL;
    p = read_key(skip_ws(p), key, sizeof key);
    if (p == NULL) {
      return "expected a key";
    }
    p = skip_ws(p);
    if (*p != ':') {
      return "expected ':' after a key";
    }
    p = skip_ws(p + 1);
    if (strcmp(key, "collisions") == 0) {
      p = read_collisions(p, &frame->collisions);
      if (p == NULL) {
        return "bad \"collisions\" (an object of pedestrian, vehicle, layout, workzone counts)";
      }
    } else if (strcmp(key, "host") == 0) {
      p = skip_value(p, 0);
      if (p == NULL) {
        return "bad \"host\" (a JSON object)";
      }
    } else {
      if (strcmp(key, "a_lon") == 0) {
        slot = &frame->a_lon;
      } else if (strcmp(key, "a_lat") == 0) {
        slot = &frame->a_lat;
      } else if (strcmp(key, "a_mag") == 0) {
        slot = &frame->a_mag;
      } else if (strcmp(key, "yaw_rate") == 0) {
        slot = &frame->yaw_rate;
      } else if (strcmp(key, "speed") == 0) {
        slot = &frame->speed;
      } else if (strcmp(key, "lat_err") == 0) {
        slot = &frame->lat_err;
      } else {
        return "unknown key";
      }
      if (slot == &frame->lat_err && strncmp(p, "null", 4) == 0) {
        frame->has_lat_err = false;
        p += 4;
      } else {
        p = read_f32(p, slot);
        if (p == NULL) {
          return "expected a number";
        }
        if (slot == &frame->lat_err) {
          frame->has_lat_err = true;
        }
      }
    }
    p = skip_ws(p);
    if (*p == '}') {
      break;
    }
    if (*p != ',') {
      return "expected ',' or '}'";
    }
    p++;
  }
  p = skip_ws(p + 1);
  if (*p != '\0') {
    return "text after the frame";
  }
  return NULL;
}
