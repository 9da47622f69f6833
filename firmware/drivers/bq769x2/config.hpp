// Build options of the BQ769x2 / BQ7690x driver (firmware/drivers/bq769x2): every option's default, meaning
// and dependencies. An image sets its values in bsp/mspm0/images/<preset>/options.cmake; the host uses these.
#pragma once

// The family the Monitor serves: 0 both (host tools and tests: the variant is read at run time), 1 BQ769x2
// only, 2 BQ7690x only. An image builds for its device's family: every variant fact is then a constant
// (except the BQ7690x cell count, which tells a BQ76905 from a BQ76907) and the other family's paths compile
// away; the front ends Bq769x2 / Bq7690x exist only in builds for their family.
#ifndef FW_BQ769X_FAMILY
#define FW_BQ769X_FAMILY 0
#endif
static_assert(FW_BQ769X_FAMILY >= 0 && FW_BQ769X_FAMILY <= 2,
              "FW_BQ769X_FAMILY: 0 both, 1 BQ769x2, 2 BQ7690x");

// The per-byte CRC-8 of the device's CRC mode (LinkConfig::crc). 0 leaves its code out for an image whose
// device runs without CRC (its configuration says link.crc = false, as every image's does: the BQ76952 and
// BQ7690x default Comm Type); such a build refuses a configuration with link.crc set (InvalidArgument on
// every operation) instead of talking to the device in the wrong mode. A device that ships in CRC mode
// (BQ7695202) needs 1.
#ifndef FW_BQ769X_CRC
#define FW_BQ769X_CRC 1
#endif

// The CRC-mode probe (MonitorConfig::probeCrc). 0 removes only a path the images never ask for: their
// configuration knows the device's mode (link.crc); probeCrc is then ignored and startProbe() uses that mode.
#ifndef FW_BQ769X_PROBE_CRC
#define FW_BQ769X_PROBE_CRC 1
#endif
static_assert(!FW_BQ769X_PROBE_CRC || FW_BQ769X_CRC, "the CRC-mode probe needs the CRC (FW_BQ769X_CRC)");

// What only the configure and balance operations use (delayed reads: the CFGUPDATE polls; startConfigure(),
// startBalance()). 0 leaves them out (they return InvalidArgument); the start-up CONFIG_UPDATE
// (FW_BQ769X_CONFIG_UPDATE, app/config.hpp) needs 1, and every image ships with it.
#ifndef FW_BQ769X_CONFIG_PATHS
#define FW_BQ769X_CONFIG_PATHS 1
#endif

// Cell balancing (Monitor::startBalance). 0 leaves it out (startBalance() returns InvalidArgument): it
// removes nothing the images use, since their application never balances. Needs the configuration paths.
#ifndef FW_BQ769X_BALANCE
#define FW_BQ769X_BALANCE 1
#endif
static_assert(!FW_BQ769X_BALANCE || FW_BQ769X_CONFIG_PATHS,
              "balancing needs the configuration paths (FW_BQ769X_CONFIG_PATHS)");

// SLEEP allowed and disallowed on request (Monitor::startSleep, pack storage: app/monitors/storage_mode.hpp).
// 0 leaves it out (startSleep() returns InvalidArgument; the run-time set-up still sends SLEEP_DISABLE): the
// images built without storage (FW_STORAGE=0).
#ifndef FW_BQ769X_SLEEP
#define FW_BQ769X_SLEEP 1
#endif

// The accumulated charge every other scan (the state of charge counts it, FW_SOC): one scan asks for
// DASTATUS6 (BQ769x2) or PASSQ (BQ7690x) first, the next reads its echo and result after its blocks
// (monitor.hpp). 0 leaves the request and the read out (ChargeCounter::valid stays false); the L1306 images,
// which build the state of charge out. The BQ7690x's wait before that read uses the delayed read of the
// configuration paths.
#ifndef FW_BQ769X_CHARGE
#define FW_BQ769X_CHARGE 1
#endif
static_assert(!FW_BQ769X_CHARGE || FW_BQ769X_CONFIG_PATHS,
              "the accumulated-charge read needs the configuration paths (FW_BQ769X_CONFIG_PATHS)");
