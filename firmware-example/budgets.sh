# Budgets of the firmware, checked by run-tests.sh (sourced by bash). Measured values and how
# they were measured: docs/FIRMWARE.md. Raise a budget only with a reason in the commit message.
#
# "vehicle" = the monitor path alone (frame source, monitor, pins; built without json-report);
# "report"  = the same plus the JSON event report over semihosting (serde-json-core, ryu).

# Proof 3: flash (text + rodata + vector table + .data image) WITHOUT the recorded route's table,
# whose size is frames x 33 bytes + 12; and RAM (data + bss + uninit), in bytes.
FLASH_CODE_MAX_VEHICLE=22528
FLASH_CODE_MAX_REPORT=51200
RAM_MAX=1024

# The monitor's state (monitor_core::MONITOR_SIZE; monitor-core asserts <= 1024 at compile time).
MONITOR_SIZE_MAX=1024

# Proof 4: guest instructions per frame (QEMU -icount shift=0 + the insncount plugin), the frame
# source's decoding and the pin writes included. The M4F figures are the goals.
M4F_AVG_INSNS_MAX=1000
M4F_WORST_INSNS_MAX=19999
# Cortex-M3 has no FPU: every f32 operation is a libcall. Regression guards only.
M3_AVG_INSNS_MAX=6000
M3_WORST_INSNS_MAX=130000

# Proof 5: stack high-water mark of a whole `run` (paint-stack), in bytes.
STACK_MAX_VEHICLE=3072
STACK_MAX_REPORT=4096

# Proof 6: the link checker image (link-checker/, Cortex-M4F only). Flash without the wire
# capture the measurement modes replay; instructions per received message, its answers and the
# pin included (median and worst, exact counts); stack of the serve runs (clean and faults).
LINK_FLASH_CODE_MAX=40960
LINK_STACK_MAX=4096
LINK_MEDIAN_INSNS_MAX=4000
LINK_WORST_INSNS_MAX=19999
