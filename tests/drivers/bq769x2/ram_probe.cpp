// Compiled for Cortex-M0+ by code_size.cmake: the sizes of these arrays are the target's sizeof of the driver
// object and of the measurement record (nm -S prints them), so RAM is measured, not estimated.
#include "drivers/bq769x2/monitor.hpp"

extern char kDriverBytes[sizeof(fw::drivers::bq769x2::Bq769x2)];
char kDriverBytes[sizeof(fw::drivers::bq769x2::Bq769x2)];
extern char kRecordBytes[sizeof(fw::drivers::bq769x2::Bq769x2Measurement)];
char kRecordBytes[sizeof(fw::drivers::bq769x2::Bq769x2Measurement)];
