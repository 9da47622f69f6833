// Scenarios: what happens to the emulated pack over time.
//
// Built-in names: idle, charge, discharge, ov-cell, ot, open-wire, comm-loss, bus-off, stale, imbalance,
// soc-discharge, soc-charge, storage. Each built-in is scenario text in the file format below, so a file can
// do whatever a built-in does. A file holds one step per line; '#' starts a comment; boards are numbered from
// 0, cells and sensors from 1:
//   <time_ms> current <mA>                             the charger (positive) or load (negative): it
//                                                      flows while the device's path for its direction is
//                                                      closed (its FETs, or the fault output that stands
//                                                      for them) and stops while it is open
//   <time_ms> cell <board> <cell> <mV>
//   <time_ms> all-cells <mV>
//   <time_ms> ramp-cell <board> <cell> <mV_per_s>      drift from the present value (0 stops the drift)
//   <time_ms> ramp-all <mV_per_s>                      every cell drifts
//   <time_ms> temp <board> <sensor> <deciK>
//   <time_ms> ramp-temp <board> <sensor> <deciK_per_s>
//   <time_ms> comm-loss on|off                         the monitor stops answering
//   <time_ms> open-wire <board> <cell>                 the sense wire below <cell> opens (cell 1: the bottom
//                                                      tap; the board's cell count + 1: the top tap)
//   <time_ms> intermittent on|off                      most monitor transactions fail
//   <time_ms> bus-off                                  the CAN controller goes bus-off
// Device faults, on the link the image has (another image warns that the step does nothing); each image
// recovers from each (bsp/twin/README.md "Device faults", tests/twin/twin_images.py faults):
//   <time_ms> stretch <us>                             the I2C device stretches SCL <us> on every byte
//                                                      (after the address and written bytes' ACK, before
//                                                      each byte it sends; 0 stops it)
//   <time_ms> stuck-scl                                the I2C device holds SCL low until its own bus
//                                                      timeout resets its interface (BQ769x: 2 s, BQ4050:
//                                                      35 ms)
//   <time_ms> stuck-sda                                the I2C device holds SDA low until the controller
//                                                      clocks SCL 8 times (a bus clear)
//   <time_ms> uart-noise <ppm>                         bit errors on the BQ79616 UART link, both
//                                                      directions, <ppm> per million bits (0 stops them)
//   <time_ms> can-error-frames <count>                 another node destroys the next <count> CAN
//                                                      transmissions (TEC + 8 each; 32 reach bus-off)
//   <time_ms> expect <fault>|any [<limit>]             the onset of the condition <fault> should catch
//   <time_ms> expect-storage on|off                    the board should publish StorageStatus.Mode storage
//                                                      (on) or normal (off) within 2 s of the step (two of
//                                                      its once-a-second frames; firmware/app/monitors/
//                                                      storage_mode.hpp)
//   <time_ms> cell-capacity <mAh>                      every emulated cell holds this much: balancing takes
//                                                      V / R from a balanced cell and its voltage falls 700
//                                                      mV over the capacity (bsp/host/emul/cell_model.hpp);
//                                                      2500 mAh until a scenario says otherwise
//   <time_ms> spread-cells <mV> <spread_mV>            every board: cell 1 at <mV>, each other cell a
//                                                      quarter, a half, three quarters or all of <spread_mV>
//                                                      above it
//   <time_ms> send <Message> [<Signal>=<value> ...]    a command from the PC or another CAN node
//   <time_ms> flood <ms> <Message> [<Signal>=<value> ...]  that command back to back for <ms>: the bus (CAN)
//                                                      or the line (SLCAN) full
//
// Numbers are decimal integers (no fractions, exponents, nan or inf). Each must lie in its range, or the
// parser stops with "file:line:col: error: ..." naming the range:
//   time 0..3600000 ms (the longest --duration); cell 0..5000 mV; current -32768..32767 mA;
//   temperature 2182..4232 (0.1 K, -55..+150 degC); ramps -5000..5000 mV/s and -2050..2050 0.1 K/s (at most
//   the whole range in a second); board 0..63, cell 1..16, sensor 1..3; capacity 1..100000 mAh; spread
//   0..500 mV; stretch 0..100000 us; noise 0..1000000 ppm; error frames 1..1000. Before the run starts,
//   checkScenario() checks boards, cells and sensors against the image (the same file:line:col errors) and
//   warns about steps the run will not reach or that the image ignores.
// A value set on a cell or sensor replaces its drift; a new drift replaces the old; a drift stops at the
// range's ends. Steps run in time order, steps with the same time in file order: a file written out of order
// is sorted so, with a warning naming each line that moved.
//
// send and flood take any message of the CAN catalogue (firmware/app/can/bms.yaml) by name and its signals
// by name, each value a decimal or 0x-hex integer or a name from the signal's value table (Setting=ocd_trip,
// Target=all, Key=key). A command's Target (1), Counter (the next of its message) and Crc (the right one)
// are filled in unless given, so a step can send a frame the firmware must refuse (Crc=0, Counter=3 twice).
// On a G3507 image the frame goes on CAN; on an L1306 image it goes as an SLCAN line on the UART (the
// channel opened with "O" before the first one). An unknown message or signal, or a value outside the
// signal's raw range, is an error at its file:line:col. flood's <ms> is 1..600000.
//
// expect names a protection fault (cell_ov, cell_uv, occ, ocd, otd, utd, device_safety, stale_data,
// comm_loss, open_wire, otc, utc, comm_rate) or `any` (every fault), once each. Without a limit the onset is
// the step's time. With one (cell_ov, cell_uv: mV; occ, ocd: mA; otc, otd, utc, utd: 0.1 K) the onset is
// the first millisecond from the step's time at which the emulated pack reaches it: any cell >= limit
// (cell_ov) or <= limit (cell_uv), the current that flows >= (occ) or <= (ocd), any sensor >= (otc, otd) or
// <= (utc, utd). The summary gives each protection event's latency from its fault's onset (or the `any`
// onset); an event detected before that onset is reported as "fault before onset".
// Scenario files are tests: an expect is met when an event of its fault (any fault for `any`) is detected at
// or after its onset, and missed when the run ends before its step, the pack never reaches its limit, or no
// such event follows the onset. The summary lists each expect as met or MISSED with the reason (--json:
// "expects", "expects_missed"), and bms-sim's exit status says it:
//   0  the run completed and every expect was met (or there was none)
//   1  the run failed (the twin stopped on an access no model covers, an output could not be written)
//   2  bad arguments or input: an option, a value out of range at file:line:col, a file too large or not a
//      file, an option the image cannot honour
//   3  the run completed and at least one expect (or expect-storage) was missed
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bmssim {

struct ValueRange {
  int32_t lo, hi;
};
inline constexpr uint32_t kMaxTimeMs = 3600000;
inline constexpr ValueRange kCellMvRange{0, 5000};
inline constexpr ValueRange kCurrentMaRange{-32768, 32767};
inline constexpr ValueRange kTempDeciKRange{2182, 4232};
// The pack every image binding starts with: cells at 3.700 V, sensors at 25 degC.
inline constexpr int32_t kStartCellMv = 3700;
inline constexpr int32_t kStartTempDeciK = 2982;

enum class Action : uint8_t {
  Current,
  Cell,
  AllCells,
  RampCell,
  RampAll,
  Temp,
  RampTemp,
  CommLoss,
  OpenWire,
  Intermittent,
  BusOff,
  Expect,
  CellCapacity,
  SpreadCells,
  Send,
  Flood,
  Stretch,
  StuckScl,
  StuckSda,
  UartNoise,
  CanErrorFrames,
  ExpectStorage,
};

// The emulated quantity an expected fault's limit applies to, and which way it is crossed.
enum class Watch : uint8_t { None, CellAbove, CellBelow, CurrentAbove, CurrentBelow, TempAbove, TempBelow };

struct Step {
  uint32_t timeMs = 0;
  Action action = Action::BusOff;
  int32_t board = 0;
  int32_t index = 0;               // cell or sensor, from 1
  int32_t value = 0;               // mV, mA, 0.1 K, a drift per second, mAh, or expect's limit
  int32_t spread = 0;              // spread-cells: the spread in mV
  bool on = false;                 // comm-loss, intermittent
  std::string fault;               // expect: a fault name or "any"
  std::string message;             // send, flood: the catalogue message
  std::vector<std::string> words;  // send, flood: its Signal=value words
  Watch watch = Watch::None;
  bool hasLimit = false;  // expect with a limit
  uint32_t line = 0;
  uint32_t boardColumn = 0, indexColumn = 0;  // where board and cell/sensor were written
};

struct Scenario {
  std::string name;  // the built-in's name or the file's path: the prefix of every message
  std::string description;
  std::vector<Step> steps;  // in time order
};

// When each expected condition began, in ms of simulated time, by fault name ("any": every fault).
using Onsets = std::map<std::string, uint32_t>;

// Messages for the user, each "<source>:<line>:<col>: error|warning: ...".
struct Diagnostics {
  std::string error;
  std::vector<std::string> warnings;
  bool unreadable = false;  // loadScenario: no such file (other read failures set `error`)
};

// The image's side of the checks the parser cannot make.
struct PackShape {
  int boards = 1, cellsPerBoard = 1, tempsPerBoard = 1;
  bool hasCurrent = true;
  bool i2c = true, uart = true, can = true;  // the device-fault steps' links
};

std::vector<std::string> builtinNames();
std::optional<Scenario> builtinScenario(const std::string& name);
// The text a built-in is made of (the file format above); empty when there is no such built-in.
std::string_view builtinText(const std::string& name);
// The fault names expect accepts, in FaultId order, then "any".
std::vector<std::string> expectableFaults();

// Parses scenario text; `source` names it in messages. On error returns nullopt and sets diag.error; adds a
// warning for each step that was out of time order.
std::optional<Scenario> parseScenario(std::string_view text, const std::string& source, Diagnostics& diag);
// Reads (at most kMaxScenarioBytes; a directory, a device or a larger file is an error naming the path)
// and parses a scenario file.
inline constexpr size_t kMaxScenarioBytes = 1 << 20;
std::optional<Scenario> loadScenario(const std::string& path, Diagnostics& diag);
// Checks the steps against the image: false with diag.error for a board, cell or sensor it does not have;
// warnings for steps after `durationMs` and current steps on an image that measures no current.
bool checkScenario(const Scenario& scenario, const PackShape& shape, uint32_t durationMs, Diagnostics& diag);

}  // namespace bmssim
