/*
 * sds_replay FRAMES.jsonl...: replays recorded frames through the C API and prints, for each
 * file (one route each, a fresh monitor each), exactly what the Rust `monitor_replay` prints:
 *
 *   route I          the route's index, from 0, in the order of the arguments
 *   event {json}     one line per event, in order (push events, then finish events)
 *   summary {json}   the route summary
 *   pins {json}      what a vehicle's alarm and comfort pins did
 *
 * The frames file is what `sds frames ... -o FILE` writes. Exit status 0, 1 on an error (a bad
 * file, a rejected frame: the message names the file and line), 2 on bad usage.
 */
#include <stdio.h>

#include "replay_file.h"

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr,
            "usage: sds_replay FRAMES.jsonl...   (one route per file, as `sds frames` writes "
            "them)\n");
    return 2;
  }
  for (int i = 1; i < argc; i++) {
    if (!sds_replay_file((uint32_t)(i - 1), argv[i])) {
      return 1;
    }
  }
  if (fflush(stdout) != 0) {
    fprintf(stderr, "sds_replay: cannot write stdout\n");
    return 1;
  }
  return 0;
}
