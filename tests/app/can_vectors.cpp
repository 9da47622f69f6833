// Prints frames packed by the generated C++ packers, each with the physical values a DBC reader must decode
// from it. The values were worked out by hand from the catalogue (raw * factor + offset), not computed here;
// "na" means the signal's not-available value, which the DBC must name "not_available".
// Output lines: <layout> <id hex> <8 data bytes hex> <Signal>=<value> ...
#include <cstdio>

#include "can/bms.hpp"

namespace {

void print(const char* layout, const fw::hal::CanFrame& f, const char* expect) {
  std::printf("%s %03X ", layout, static_cast<unsigned>(f.id));
  for (uint8_t b : f.data)
    std::printf("%02X", b);
  std::printf(" %s\n", expect);
}

}  // namespace

int main() {
  using namespace fw::can::bms;
  PackSummary s;
  s.packVoltage = 4812;
  s.packCurrent = -1234;
  s.stateOfCharge = 87;
  s.chargeFet = 1;
  s.dischargeFet = 0;
  s.faultOutput = 1;
  s.dataValid = 1;
  s.counter = 9;
  s.activeFaults = 0x0101;
  print("native", s.pack(),
        "PackVoltage=481.2 PackCurrent=-12.34 StateOfCharge=87 ChargeFet=1 DischargeFet=0 FaultOutput=1 "
        "DataValid=1 Counter=9 ActiveFaults=257");
  s.packVoltage = 51200;  // 64 boards x 16 cells x 5 V
  s.packCurrent = -32767;
  s.activeFaults = 0x0200;  // open_wire
  print("native", s.pack(),
        "PackVoltage=5120 PackCurrent=-327.67 StateOfCharge=87 ChargeFet=1 DischargeFet=0 FaultOutput=1 "
        "DataValid=1 Counter=9 ActiveFaults=512");
  s.packVoltage = 0xFFFF;
  s.packCurrent = INT16_MIN;
  s.stateOfCharge = 255;
  s.dataValid = 0;
  print("native", s.pack(),
        "PackVoltage=na PackCurrent=na StateOfCharge=na ChargeFet=1 DischargeFet=0 FaultOutput=1 DataValid=0 "
        "Counter=9 ActiveFaults=512");
  s.chargeFet = 3;  // nothing confirms the paths (comm loss)
  s.dischargeFet = 3;
  s.activeFaults = 0x0900;  // utc, comm_loss
  print(
      "native", s.pack(),
      "PackVoltage=na PackCurrent=na StateOfCharge=na ChargeFet=na DischargeFet=na FaultOutput=1 DataValid=0 "
      "Counter=9 ActiveFaults=2304");

  StateOfCharge q;
  q.soc = 437;
  q.remainingCapacity = 1092;
  q.fullChargeCapacity = 1048574;  // the largest capacity a pack file takes
  q.basis = 1;                     // ocv
  print("native", q.pack(), "Soc=43.7 RemainingCapacity=1092 FullChargeCapacity=1048574 Basis=1");
  q.soc = 0xFFFF;
  q.remainingCapacity = q.fullChargeCapacity = 0xFFFFF;
  q.basis = 15;
  print("native", q.pack(), "Soc=na RemainingCapacity=na FullChargeCapacity=na Basis=na");

  CellExtremes e;
  e.maxCellVoltage = 4201;
  e.maxCellIndex = 17;
  e.minCellVoltage = 2999;
  e.minCellIndex = 1023;
  print("native", e.pack(), "MaxCellVoltage=4201 MaxCellIndex=17 MinCellVoltage=2999 MinCellIndex=1023");
  e.maxCellVoltage = e.maxCellIndex = e.minCellVoltage = e.minCellIndex = 0xFFFF;
  print("native", e.pack(), "MaxCellVoltage=na MaxCellIndex=na MinCellVoltage=na MinCellIndex=na");

  TemperatureExtremes t;
  t.maxTemperature = 3332;  // 60.05 degC
  t.minTemperature = 2532;  // -19.95 degC
  t.maxTemperatureIndex = 3;
  t.minTemperatureIndex = 0;
  print("native", t.pack(),
        "MaxTemperature=60.05 MinTemperature=-19.95 MaxTemperatureIndex=3 MinTemperatureIndex=0");
  t.maxTemperature = t.minTemperature = t.maxTemperatureIndex = t.minTemperatureIndex = 0xFFFF;
  print("native", t.pack(),
        "MaxTemperature=na MinTemperature=na MaxTemperatureIndex=na MinTemperatureIndex=na");

  ProtectionEvent p;
  p.activeFaults = 0x0001;
  p.newlyTripped = 0x0001;
  p.newlyCleared = 0x0100;
  p.commErrors = 65535;
  print("native", p.pack(), "ActiveFaults=1 NewlyTripped=1 NewlyCleared=256 CommErrors=65535");

  CellVoltages c;
  c.board = 5;
  c.frameIndex = 2;  // cells 7..9
  c.status = 0;
  c.cell[0] = 3700;
  c.cell[1] = 3701;
  c.cell[2] = 3702;
  print("native", c.pack(), "Board=5 FrameIndex=2 Status=0 Cell07=3700 Cell08=3701 Cell09=3702");
  c.frameIndex = 5;  // cell 16 only
  c.cell[0] = 4100;
  c.cell[1] = 0xFFFF;
  c.cell[2] = 0xFFFF;
  print("native", c.pack(), "Board=5 FrameIndex=5 Status=0 Cell16=4100");
  c.board = 63;
  c.frameIndex = 1;  // cells 4..6, the tap between 4 and 5 open
  c.status = 4;
  c.cell[0] = 0xFFFF;
  c.cell[1] = 0xFFFF;
  c.cell[2] = 3650;
  print("native", c.pack(), "Board=63 FrameIndex=1 Status=4 Cell04=na Cell05=na Cell06=3650");

  Temperatures tt;
  tt.board = 1;
  tt.frameIndex = 0;  // sensors 1..3
  tt.status = 0;
  tt.temp[0] = 2982;  // 25.05 degC
  tt.temp[1] = 2732;  // 0.05 degC
  tt.temp[2] = 0xFFFF;
  print("native", tt.pack(), "Board=1 FrameIndex=0 Status=0 Temp1=25.05 Temp2=0.05 Temp3=na");
  tt.frameIndex = 1;  // sensor 4 (slots 5 and 6: no sensor, not in the DBC)
  tt.temp[0] = 3232;  // 50.05 degC
  tt.temp[1] = 0xFFFF;
  print("native", tt.pack(), "Board=1 FrameIndex=1 Status=0 Temp4=50.05");

  TiCellVoltages ti;
  ti.vCell[0] = 0x16C0;  // 5824 * 190.73 uV = 1.11081152 V (seed 001: "1.1108 V")
  ti.vCell[1] = 0x16BC;
  ti.vCell[2] = 0x16B4;
  ti.vCell[3] = -1;
  print("ti", ti.pack(), "VCell1=1.11081152 VCell2=1.1100486 VCell3=1.10852276 VCell4=-0.00019073");

  // Startup goes out in either layout, so both DBCs decode it.
  Startup up;
  up.resetCause = 0x1B;  // software SYSRST: the fault record survived
  up.firmwareMajor = 0;
  up.firmwareMinor = 1;
  up.firmwarePatch = 0;
  up.faultModule = 30;
  up.faultLine = 0xFFFE;
  up.protectionLogEntries = 3;  // the record store restored three trips
  up.faultSource = 1;           // the fault of this reset, now kept in flash
  print("native", up.pack(),
        "ResetCause=27 FirmwareMajor=0 FirmwareMinor=1 FirmwarePatch=0 FaultModule=30 FaultLine=65534 "
        "ProtectionLogEntries=3 FaultSource=1");
  up.resetCause = 0x0E;  // WWDT0: a BOOTRST, nothing survived
  up.faultModule = Startup::kFaultModuleNotAvailable;
  up.faultLine = Startup::kFaultLineNotAvailable;
  up.protectionLogEntries = Startup::kProtectionLogEntriesNotAvailable;  // an image without the store
  up.faultSource = Startup::kFaultSourceNotAvailable;
  print("ti", up.pack(),
        "ResetCause=14 FirmwareMajor=0 FirmwareMinor=1 FirmwarePatch=0 FaultModule=na FaultLine=na "
        "ProtectionLogEntries=na FaultSource=na");
  return 0;
}
