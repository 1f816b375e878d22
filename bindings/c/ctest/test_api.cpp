// test_api.cpp: the C API from C++17 (g++ -std=c++17 -Wall -Wextra -Werror, linked statically
// against libsds_monitor.a, run under valgrind): the header is valid C++, its types are plain
// standard-layout data, and a small C++ wrapper replays the frames files given, printing the
// lines `monitor_replay` prints (its own formatter, independent of examples/sds_lines.c).
//
//   test_api_cpp [FRAMES.jsonl...]
//
// The closing line on stderr is "c++ api: N passed, M failed"; the exit status is 1 on a failure.
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>
#include <type_traits>

#include "frames_jsonl.h"
#include "sds_monitor.h"

static_assert(std::is_standard_layout<sds_frame>::value && std::is_trivial<sds_frame>::value,
              "sds_frame is plain data");
static_assert(std::is_standard_layout<sds_events>::value && std::is_trivial<sds_events>::value,
              "sds_events is plain data");
static_assert(std::is_trivial<sds_monitor_storage>::value, "storage is plain memory");
static_assert(alignof(sds_monitor_storage) >= 8, "storage is 8-byte aligned");
static_assert(std::is_same<std::underlying_type<sds_result>::type, uint32_t>::value,
              "sds_result is a 32-bit code in C++ too");

namespace {

unsigned passed = 0;
unsigned failed = 0;

void check(bool ok, const char *what, int line) {
  if (ok) {
    ++passed;
  } else {
    ++failed;
    std::cerr << "test_api.cpp:" << line << ": FAILED: " << what << "\n";
  }
}
#define CHECK(cond) check((cond), #cond, __LINE__)

// A monitor in memory this object owns: no allocation, nothing to free.
class Monitor {
 public:
  sds_result init(const sds_config &config) {
    return sds_monitor_init(handle(), sizeof storage_, &config);
  }
  sds_result push(const sds_frame &frame, sds_events &events) {
    return sds_monitor_push(handle(), &frame, &events);
  }
  sds_result finish(sds_events &events, sds_summary &summary) {
    return sds_monitor_finish(handle(), &events, &summary);
  }

 private:
  sds_monitor *handle() { return reinterpret_cast<sds_monitor *>(&storage_); }
  sds_monitor_storage storage_{};
};

std::string f32(float v) {
  std::array<char, SDS_NUMBER_TEXT_MAX> buf{};
  size_t n = 0;
  if (!std::isfinite(v)) return "null";
  if (sds_format_f32(v, buf.data(), buf.size(), &n) != SDS_RESULT_OK) return "?";
  return std::string(buf.data(), n);
}

std::string b(bool v) { return v ? "true" : "false"; }
std::string u(uint32_t v) { return std::to_string(v); }

std::string event_json(const sds_event &e) {
  switch (e.kind) {
    case SDS_EVENT_COLLISION: {
      const auto &v = e.collision;
      const auto &c = v.collisions;
      return "{\"collision\":{\"frame\":" + u(v.frame) + ",\"collisions\":{\"pedestrian\":" +
             u(c.pedestrian) + ",\"vehicle\":" + u(c.vehicle) + ",\"layout\":" + u(c.layout) +
             ",\"workzone\":" + u(c.workzone) + "},\"speed\":" + f32(v.speed) +
             ",\"decelerated\":" + b(v.decelerated) + ",\"exempt\":" + b(v.exempt) + "}}";
    }
    case SDS_EVENT_COMFORT: {
      const auto &v = e.comfort;
      const auto &f = v.failed;
      return "{\"comfort\":{\"chunk\":" + u(v.chunk) + ",\"frames\":" + u(v.frames) +
             ",\"failed\":{\"lon_acc\":" + b(f.lon_acc) + ",\"lat_acc\":" + b(f.lat_acc) +
             ",\"mag_jerk\":" + b(f.mag_jerk) + ",\"lon_jerk\":" + b(f.lon_jerk) +
             ",\"yaw_acc\":" + b(f.yaw_acc) + ",\"yaw_rate\":" + b(f.yaw_rate) + "}}}";
    }
    case SDS_EVENT_LATERAL: {
      const auto &v = e.lateral;
      const char *band = v.band == SDS_BAND_CRITICAL    ? "critical"
                         : v.band == SDS_BAND_ANOMALOUS ? "anomalous"
                                                        : "normal";
      return "{\"lateral\":{\"chunk\":" + u(v.chunk) + ",\"max_excess\":" + f32(v.max_excess) +
             ",\"band\":\"" + band + "\"}}";
    }
    default:
      return "?";
  }
}

std::string summary_json(const sds_summary &s) {
  const auto &f = s.comfort.failed;
  return "{\"frames\":" + u(s.frames) + ",\"comfort\":{\"chunks\":" + u(s.comfort.chunks) +
         ",\"comfortable\":" + u(s.comfort.comfortable) + ",\"failed\":{\"lon_acc\":" +
         u(f.lon_acc) + ",\"lat_acc\":" + u(f.lat_acc) + ",\"mag_jerk\":" + u(f.mag_jerk) +
         ",\"lon_jerk\":" + u(f.lon_jerk) + ",\"yaw_acc\":" + u(f.yaw_acc) +
         ",\"yaw_rate\":" + u(f.yaw_rate) + "}},\"lateral\":{\"chunks\":" +
         u(s.lateral.chunks) + ",\"scored_chunks\":" + u(s.lateral.scored_chunks) +
         ",\"anomalous\":" + u(s.lateral.anomalous) + ",\"critical\":" +
         u(s.lateral.critical) + "},\"collisions\":{\"aligned\":" + u(s.collisions.aligned) +
         ",\"exempt\":" + u(s.collisions.exempt) + ",\"nodecel\":" + u(s.collisions.nodecel) +
         "}}";
}

struct Pins {
  bool alarm = false;
  uint32_t alarm_rises = 0;
  bool comfort = false;
  uint32_t comfort_rises = 0;

  void see(const sds_event &e) {
    bool raise = false;
    if (e.kind == SDS_EVENT_COLLISION) raise = e.collision.nodecel;
    if (e.kind == SDS_EVENT_LATERAL) raise = e.lateral.band == SDS_BAND_CRITICAL;
    if (e.kind == SDS_EVENT_COMFORT) {
      if (!e.comfort.comfortable && !comfort) ++comfort_rises;
      comfort = !e.comfort.comfortable;
    }
    if (raise && !alarm) {
      alarm = true;
      ++alarm_rises;
    }
  }
  std::string json() const {
    return "{\"alarm\":" + b(alarm) + ",\"alarm_rises\":" + u(alarm_rises) +
           ",\"comfort\":" + b(comfort) + ",\"comfort_rises\":" + u(comfort_rises) + "}";
  }
};

bool replay(uint32_t index, const char *path) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << "test_api_cpp: " << path << ": cannot open\n";
    return false;
  }
  Monitor m;
  if (m.init(sds_config_default()) != SDS_RESULT_OK) return false;
  Pins pins;
  sds_events events{};
  sds_summary summary{};
  auto print = [&pins](const sds_events &ev) {
    for (uint32_t i = 0; i < ev.len; ++i) {
      pins.see(ev.events[i]);
      std::cout << "event " << event_json(ev.events[i]) << "\n";
    }
  };
  std::cout << "route " << index << "\n";
  std::string line;
  unsigned long number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    sds_frame frame{};
    if (const char *err = sds_frame_parse_json(line.c_str(), &frame)) {
      std::cerr << "test_api_cpp: " << path << " line " << number << ": " << err << "\n";
      return false;
    }
    sds_result r = m.push(frame, events);
    if (r != SDS_RESULT_OK) {
      std::cerr << "test_api_cpp: " << path << " line " << number << ": " << sds_result_str(r)
                << "\n";
      return false;
    }
    print(events);
  }
  if (m.finish(events, summary) != SDS_RESULT_OK) return false;
  print(events);
  std::cout << "summary " << summary_json(summary) << "\n";
  std::cout << "pins " << pins.json() << "\n";
  return true;
}

void test_errors() {
  Monitor m;
  sds_events ev{};
  sds_summary s{};
  sds_frame f{};
  f.speed = 5.0f;
  // Never initialised (zeroed storage), then a bad configuration, then a good one.
  CHECK(m.push(f, ev) == SDS_RESULT_NOT_INITIALIZED);
  sds_config c = sds_config_default();
  c.min_chunk = 3;
  CHECK(m.init(c) == SDS_RESULT_CONFIG_MIN_CHUNK);
  CHECK(m.init(sds_config_default()) == SDS_RESULT_OK);
  CHECK(sds_monitor_push(nullptr, &f, &ev) == SDS_RESULT_NULL_POINTER);
  CHECK(sds_monitor_init(nullptr, 0, nullptr) == SDS_RESULT_NULL_POINTER);
  alignas(8) unsigned char small[8] = {};
  CHECK(sds_monitor_init(reinterpret_cast<sds_monitor *>(small), sizeof small, &c) ==
        SDS_RESULT_BUFFER_TOO_SMALL);
  f.yaw_rate = std::numeric_limits<float>::quiet_NaN();
  CHECK(m.push(f, ev) == SDS_RESULT_FRAME_YAW_RATE_NOT_FINITE);
  f.yaw_rate = 0.0f;
  CHECK(m.push(f, ev) == SDS_RESULT_OK);
  CHECK(m.finish(ev, s) == SDS_RESULT_OK);
  CHECK(s.frames == 1);
  CHECK(m.push(f, ev) == SDS_RESULT_FINISHED);
  CHECK(std::string(sds_result_str(SDS_RESULT_FINISHED)).find("finished") != std::string::npos);
}

}  // namespace

int main(int argc, char **argv) {
  test_errors();
  bool ok = true;
  for (int i = 1; i < argc && ok; ++i) ok = replay(static_cast<uint32_t>(i - 1), argv[i]);
  CHECK(ok);
  std::cout.flush();
  CHECK(static_cast<bool>(std::cout));
  std::cerr << "c++ api: " << passed << " passed, " << failed << " failed\n";
  return failed == 0 ? 0 : 1;
}
