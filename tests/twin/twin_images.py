#!/usr/bin/python3
"""The five firmware images on the MSPM0 twin (bms-sim --elf), judged by what the board publishes.

usage: twin_images.py <check> <bms-sim> <dbc-dir> <elf> <scratch-dir>
checks:
  ov-cell     the ov-cell scenario trips cell_ov and the FETs / fault output act within one scan period of the
              onset; every native frame decodes with bms_native.dbc; PackSummary comes every scan period
              +-1 ms; the contract keys and the twin's CPU figures are in --json; no reset, no HardFault
  comm-loss   the monitor stops answering at 2 s: comm_loss is published, the board keeps publishing, no reset;
              every frame decodes with bms_native.dbc
  bus-off     (CAN images) the controller goes bus-off at 2 s: PackSummary resumes within 150 ms of the onset;
              every frame decodes with bms_native.dbc
  agreement   the host build and the image on the twin, same scenario (ov-cell), from the first cycle each
              publishes valid data: the same frames of the messages the image sends, in the same order, each
              within one scan period of its twin, and the same published states and protection trips within
              one scan period; and a step on the scan grid detected by the scan of that tick on both
  open-wire-taps
              the bottom and the top sense wire opened: open_wire detected by the scan of that tick, on the host
              and on the twin, and no path reported on
  agreement-intermittent
              an intermittent link (most transactions failing for 3 s), its onset shifted 0, 1, 2, 3 and 50 ms
              against the scan grid: on the host and on the twin comm_rate is published within 1 s of the
              onset and held with the fault output until the link heals, then cleared within 2.5 s
  slcan       (L1306 images) --slcan FILE on the twin holds exactly the text the image's UART0 sent on PA8: one
              't' line per CR, the same frames in the same order as --candump's decoded lines
  load        the emulated load and charger stop when the image opens their path (FETs or fault output)
  options     options the image cannot honour (--devices on a one-device image, --can-layout ti) exit 2
  gauge-soc   (BQ4050) StateOfCharge follows the current the emulated gauge counts
  profile     --profile FILE: the format of bsp/twin/profiler.hpp; the function rows and the exception rows
              each add up to the busy cycles, sleep is the rest; the I2C/UART handler was entered; --profile
              without --elf exits 2. Prints the top ten functions (REPORT)
  faults      every device fault of scenario.hpp the image's links have (SCL stretch within and beyond the
              stretch limit, SCL and SDA held, UART noise, CAN error frames), on the twin and on the host
              build: the image publishes valid data again within RECOVERY_MS of the fault's end (and PackSummary
              keeps coming, but for the bus-off error frames cause); a stretch within the limit loses nothing
  no-crystal  (CAN images) a board without the HFXT crystal (bms-sim --no-crystal), 2 s: the image's wait for
              the crystal ends (bsp/mspm0 startHfxt gives up after ~5 ms; HFXT-WAIT-UNBOUNDED stops a wait still
              polling 20 ms after the start-up monitor's verdict), no CAN frame, no reset, no rule or warning,
              and the monitor goes on scanning (protection does not need the CAN bus). The MCAN is never
              powered then, and nothing reads it (McanBus answers off the bus without a register access)
  soc-count   (the BQ769x images with FW_SOC) 5 minutes of the soc-discharge scenario: StateOfCharge within 2 % of the emulator's
              true value
  storage     (the BQ769x images with FW_STORAGE) the storage scenario, 35 s: StorageMode accepted, 1 s scans, the
              worst-case age published, no fault, the load ends storage (tests/tools check_storage)
Every check also finds StateOfCharge in each PackSummary and the StateOfCharge message as the image can know it:
always from the BQ4050's gauge, never on the BQ79616 image (no current input; it was 0 %) nor on an image that
builds it out (FW_SOC=0: L1306-BQ76952), 0..100 % or not available (until known) on the other BQ769x images, and PackSummary.Counter stepping by the number of 100 ms cycles between summaries (a gap per lost one).
Prints REPORT lines (CPU load, interrupt latency, longest ISR, the twin's speed).
Exit 77 (skipped) when the ELF has not been built (./ci/test builds every image before it tests)."""
import json
import os
import subprocess
import sys
import time

import canmatrix
import canmatrix.formats

# The host runs' checks (tests/tools): the same contract keys and the same candump reader (absolute times).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))
from bms_sim_acceptance import (CONTRACT_KEYS, IMAGES, check_counter, check_gauge_soc,  # noqa: E402
                                check_load_paths, check_options, check_soc_count, check_soc_published,
                                check_storage, read_candump, read_slcan_text)
TWIN_KEYS = ["cpu_load_pct", "isr_max_us", "wake_latency_max_us"]
FAULTS = ["cell_ov", "cell_uv", "occ", "ocd", "otd", "utd", "device_safety", "stale_data", "comm_loss", "open_wire",
          "otc", "utc", "comm_rate"]
PACK_SUMMARY, PROTECTION_EVENT, STARTUP = 0x100, 0x103, 0x1F0
PERIOD_TOLERANCE_MS = 1.0  # PackSummary period against the configured scan period (check_ov_cell says why)


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(sim, args):
    started = time.monotonic()
    result = subprocess.run([sim, *args], capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"bms-sim {' '.join(args)} exited {result.returncode}: {result.stderr.strip()}")
    return json.loads(result.stdout), time.monotonic() - started


def simulate(sim, scratch, name, scenario, duration, source):
    log = os.path.join(scratch, f"{name}-{os.path.basename(scenario)}.log")
    summary, seconds = run(sim, [*source, "--scenario", scenario, "--duration", str(duration), "--json",
                                 "--candump", log])
    frames = read_candump(log)
    check_published(summary["image"], frames, scenario)
    return summary, frames, seconds


def check_published(image, frames, scenario):
    """What every run must show: StateOfCharge always from the gauge, never on the BQ79616 image (bms.yaml: 255
    is not available; it once sent 0 % from its zero-filled state), 0..100 or not available (until the first
    value) on the BQ769x images' coulomb count; and a PackSummary.Counter gap for each summary that never went
    out, and none otherwise."""
    for t, ident, d in frames:
        if ident != PACK_SUMMARY or not d[7] & 0x80:  # DataValid
            continue
        soc = d[4]
        if IMAGES[image].gauge_soc:
            bad = soc == 255
        elif not IMAGES[image].counts_soc:
            bad = soc != 255  # no current input (BQ79616), or the state of charge built out (FW_SOC=0)
        else:
            bad = soc != 255 and soc > 100
        if bad:
            fail(f"{scenario}: PackSummary at {t:.3f} ms has StateOfCharge {soc} on {image}")
    check_soc_published(image, frames, scenario)
    if IMAGES[image].output == "can":
        check_counter(frames, scenario)


def twin_report(summary, seconds, image, scenario):
    mips = int(summary.get("twin_instructions", 0)) / seconds / 1e6
    print(f"REPORT twin.{image}.{scenario}: cpu_load {summary['cpu_load_pct']:.3f} %, worst interrupt latency "
          f"{summary['wake_latency_max_us']:.2f} us, longest ISR {summary['isr_max_us']:.2f} us; "
          f"{summary['sim_time_ms'] / 1000:.1f} s simulated in {seconds:.2f} s ({mips:.1f} MIPS)")


def check_healthy(summary):
    for key in CONTRACT_KEYS + TWIN_KEYS:
        if key not in summary:
            fail(f"--json has no '{key}'")
    if summary["twin_resets"] != 0:
        fail(f"the MCU reset {summary['twin_resets']} times")
    if summary["twin_hard_faults"] != 0:
        fail(f"{summary['twin_hard_faults']} HardFaults")
    if summary["twin_warnings"]:
        fail(f"the twin noticed: {summary['twin_warnings']}")


def decode_all(dbc_dir, frames):
    """Every frame the board sent decodes with bms_native.dbc."""
    db = canmatrix.formats.loadp_flat(os.path.join(dbc_dir, "bms_native.dbc"))
    for t, ident, data in frames:
        frame = db.frame_by_id(canmatrix.ArbitrationId(ident))
        if frame is None:
            fail(f"frame {ident:03X} at {t:.3f} ms is not in bms_native.dbc")
        frame.decode(bytearray(data))


def pack_summaries(frames):
    """(time, ChargeFet, DischargeFet, FaultOutput, DataValid, ActiveFaults) of each PackSummary (bms.yaml:
    ChargeFet bits 40-41 and DischargeFet 42-43, 3 = not available; ActiveFaults 48-61, FaultOutput 62,
    DataValid 63)."""
    out = []
    for t, ident, d in frames:
        if ident == PACK_SUMMARY and len(d) == 8:
            tail = int.from_bytes(d[6:8], "little")
            out.append((t, d[5] & 3, (d[5] >> 2) & 3, (tail >> 14) & 1, (tail >> 15) & 1, tail & 0x3FFF))
    return out


def check_ov_cell(sim, dbc_dir, elf, image, scratch):
    summary, frames, seconds = simulate(sim, scratch, f"twin-{image}", "ov-cell", 4000, ["--elf", elf])
    check_healthy(summary)
    events = [e for e in summary["protection_events"] if e["fault"] == "cell_ov"]
    if not events or events[0]["fets_off_ms"] is None:
        fail(f"no cell_ov trip that acted: {summary['protection_events']}")
    latency = events[0]["fets_off_ms"] - events[0]["onset_ms"]
    if latency > summary["scan_period_ms"]:
        fail(f"cell_ov acted {latency:.3f} ms after the onset, over one scan period")
    if summary["scans"] < 30:
        fail(f"only {summary['scans']} scans in 4 s")
    decode_all(dbc_dir, frames)
    summaries = pack_summaries(frames)
    if not summaries:
        fail("no PackSummary published")
    # The publish period as the image keeps it. Each scan starts at its timer's deadline: TimgClock wakes the
    # CPU on the deadline's 1 us timer tick at any distance, plus the wake latency (under 10 us on the twin);
    # PackSummary follows the scan after its bus time and the CAN queue, which differ from scan to scan by at
    # most a frame or two in the queue (0.25 ms each at 500 kbit/s) and the device's stretches. +-1 ms holds
    # that with margin and catches a deadline armed late (the old 16.4 ms alarm limit: 98.3 .. 116.1 ms).
    gaps = [b[0] - a[0] for a, b in zip(summaries, summaries[1:])]
    print(f"REPORT twin.{image}.pack_summary_period_ms: {min(gaps):.1f} .. {max(gaps):.1f} "
          f"(configured {summary['scan_period_ms']})")
    off = [g for g in gaps if abs(g - summary["scan_period_ms"]) > PERIOD_TOLERANCE_MS]
    if off:
        fail(f"PackSummary periods {min(gaps):.3f} .. {max(gaps):.3f} ms, not within {PERIOD_TOLERANCE_MS} ms of "
             f"{summary['scan_period_ms']} ms")
    print(f"REPORT twin.{image}.ov_cell.onset_to_off_ms={latency:.3f} (budget {summary['scan_period_ms']}); "
          f"{len(frames)} frames decoded with bms_native.dbc; scan bus {summary['scan_bus_us']:.0f} us")
    twin_report(summary, seconds, image, "ov-cell")


def check_comm_loss(sim, dbc_dir, elf, image, scratch):
    summary, frames, seconds = simulate(sim, scratch, f"twin-{image}", "comm-loss", 4000, ["--elf", elf])
    check_healthy(summary)
    decode_all(dbc_dir, frames)
    late = [s for s in pack_summaries(frames) if s[0] > 3000.0]
    if not late:
        fail("no PackSummary after the link went silent")
    if not any(s[5] & (1 << FAULTS.index("comm_loss")) for s in late):
        fail(f"comm_loss is never published after the monitor went silent: {late[-1]}")
    if any(s[4] for s in late):
        fail("a PackSummary calls the data valid a second after the monitor went silent")
    # The wire shows the board trying again (bms-sim counts what it sees: failed transactions and scans,
    # recoveries).
    tries = summary["comm_errors"] + summary["scan_failures"] + summary["recoveries"]
    if tries == 0:
        fail("the wire shows no failed transaction, failed scan or recovery after the monitor went silent")
    # The BQ76952 boards open the paths through CFETOFF / DFETOFF when the link is gone (README "Protection":
    # no I2C needed): the device's FETs go off with the detection, not never (the twin once left the pins
    # unwired, and the FETs of a silent link stayed on).
    if IMAGES[image].device == "bq76952":
        for e in summary["protection_events"]:
            if e["fets_off_ms"] is None or e["fets_off_ms"] - e["detected_ms"] > 2.0:
                fail(f"{e['fault']} detected at {e['detected_ms']} ms: the FETs went off at {e['fets_off_ms']} ms "
                     "(CFETOFF / DFETOFF, within 2 ms)")
        if summary["charge_path_closed"] or summary["discharge_path_closed"]:
            fail("a path is still closed after the link went silent")
    twin_report(summary, seconds, image, "comm-loss")
    print(f"REPORT twin.{image}.comm-loss.wire: {summary['scans']} scans ({summary['scan_failures']} failed), "
          f"{summary['comm_errors']} comm errors, {summary['recoveries']} recoveries")


def check_bus_off(sim, dbc_dir, elf, image, scratch):
    summary, frames, seconds = simulate(sim, scratch, f"twin-{image}", "bus-off", 4000, ["--elf", elf])
    check_healthy(summary)
    decode_all(dbc_dir, frames)
    after = [t for t, ident, _ in frames if ident == PACK_SUMMARY and t > 2000.0]
    if not after or after[0] > 2150.0:
        fail(f"PackSummary did not resume after the bus-off at 2000 ms (next at {after[:1]})")
    spans = summary["bus_off"]
    if len(spans) != 1 or spans[0]["at_ms"] != 2000.0 or not 2.816 <= (spans[0]["recovery_ms"] or 0) <= 10.0:
        fail(f"--json bus_off: {spans}")
    twin_report(summary, seconds, image, "bus-off")
    # The bus knocked off again every millisecond for one publish period (a step while it is still off does
    # nothing): the summary due in that period is refused whatever the image's phase, and the Counter must
    # show it (it did not: a cycle due during a bus-off was never counted); check_published() holds every
    # step to the cycles between the summaries.
    path = os.path.join(scratch, f"{image}-bus-off-sweep.txt")
    with open(path, "w") as f:
        f.writelines(f"{2000 + i} bus-off\n" for i in range(100))
    summary, frames, _ = simulate(sim, scratch, f"twin-{image}", path, 3000, ["--elf", elf])
    skipped = max(b["pack_summary_counter_skipped"] or 0 for b in summary["bus_off"])
    if len(summary["bus_off"]) < 20 or skipped < 1:
        fail(f"a period of bus-offs: {len(summary['bus_off'])} reported, the Counter skipped {skipped}")
    print(f"REPORT twin.{image}.bus_off: recovery {spans[0]['recovery_ms']:.3f} ms; a period of bus-offs "
          f"({len(summary['bus_off'])}) cost {skipped} summaries, the Counter skipped as many")


def trips(frames):
    """The published protection trips: ProtectionEvent NewlyTripped where the image sends ProtectionEvent,
    else the bits rising in PackSummary.ActiveFaults."""
    out = []
    if any(ident == PROTECTION_EVENT for _, ident, _ in frames):
        for t, ident, d in frames:
            if ident == PROTECTION_EVENT:
                bits = int.from_bytes(d[2:4], "little")
                out += [(t, i) for i in range(16) if bits >> i & 1]
    else:
        active = 0
        for t, *_, faults in pack_summaries(frames):
            out += [(t, i) for i in range(16) if (faults & ~active) >> i & 1]
            active = faults
    return out


def first_valid(frames):
    return next((s[0] for s in pack_summaries(frames) if s[4]), None)


def agree(sim, elf, image, scratch, scenario, duration, name):
    """Runs `scenario` on the host build and on the twin and checks that they agree; returns the twin's
    published trips."""
    period = 100.0  # every image's scan period (ms)
    _, host, _ = simulate(sim, scratch, f"host-{image}-{name}", scenario, duration, ["--image", image])
    # --image with --elf: bms-sim runs the twin itself, not the image's host simulator (bms-sim-<preset>).
    summary, twin, _ = simulate(sim, scratch, f"twin-{image}-{name}", scenario, duration,
                                ["--elf", elf, "--image", image])
    check_healthy(summary)
    # The host simulator is built with the image's options (bms-sim-<preset>), so both send the same messages;
    # compare the messages the image sends all the same. Both start with the first cycle that publishes valid
    # data: the image boots and brings its monitor up on real time, the host from t = 0.
    # The Startup message carries the MCU's reset cause, which the host build has not: compared without it.
    ids = {i for _, i, _ in twin} - {STARTUP}
    host_start, twin_start = first_valid(host), first_valid(twin)
    if twin_start is None:
        fail(f"{name}: the twin never publishes valid data")
    if host_start is None:
        fail(f"{name}: the host never publishes valid data")
    start = max(host_start, twin_start) - period / 2
    host = [f for f in host if f[1] in ids and f[0] >= start]
    twin = [f for f in twin if f[1] in ids and f[0] >= start]
    n = min(len(host), len(twin))
    if n < 20 or abs(len(host) - len(twin)) > len(ids):
        fail(f"{name}: host {len(host)} frames, twin {len(twin)} frames of the same messages after the start")
    worst = 0.0
    for (th, ih, _), (tt, it, _) in zip(host[:n], twin[:n]):
        if ih != it:
            fail(f"{name}: frame {ih:03X} at {th:.3f} ms on the host is {it:03X} at {tt:.3f} ms on the twin")
        worst = max(worst, abs(th - tt))
        if abs(th - tt) > period:
            fail(f"{name}: frame {ih:03X} at {th:.3f} ms on the host comes at {tt:.3f} ms on the twin")
    # What the board says about its state: the FET/fault flags and the active faults, change by change.
    def states(frames):
        changes, last = [], None
        for t, chg, dsg, out, _, faults in pack_summaries(frames):
            if (chg, dsg, out, faults) != last:
                changes.append((t, (chg, dsg, out, faults)))
                last = (chg, dsg, out, faults)
        return changes
    # The same changes in the same order, each within one scan period of the host's.
    for what, h, t, label in (("state", states(host), states(twin), str),
                              ("trip", trips(host), trips(twin), lambda f: FAULTS[f])):
        if [s for _, s in h] != [s for _, s in t]:
            fail(f"{name}: the published {what}s differ: host {h}, twin {t}")
        for (a, s), (b, _) in zip(h, t):
            if abs(a - b) > period:
                fail(f"{name}: the {what} {label(s)} published at {a:.3f} ms on the host comes at {b:.3f} ms "
                     "on the twin")
    tt = trips(twin)
    print(f"REPORT twin.{image}.agreement.{name}: {n} frames ({len(ids)} messages) and {len(tt)} trips as on the "
          f"host, worst frame time difference {worst:.3f} ms; first valid data at {host_start:.1f} ms (host) "
          f"and {twin_start:.1f} ms (twin, from reset)")
    return tt


def check_agreement(sim, elf, image, scratch):
    # 4 s: past the cell_ov trip (about 2.3 s) and the monitor's own over-voltage protection (3.5 s), which
    # both builds configure at start-up (CONFIG_UPDATE).
    agree(sim, elf, image, scratch, "ov-cell", 4000, "ov-cell")
    check_step_same_scan(sim, elf, image, scratch)


def check_step_same_scan(sim, elf, image, scratch):
    """A step on the scan grid (cell 2 to 4.30 V at 2 s) is detected by the scan at that tick on the host and
    on the twin alike (both scan on the clock's 100 ms grid; on the host a step at t comes before the
    firmware's tick at t, as on the twin): cell_ov within the scan period that starts with the step, on both.
    Before, the host saw it one scan later than the twin."""
    path = os.path.join(scratch, "step-on-grid.txt")
    with open(path, "w") as f:
        f.write("2000 cell 0 2 4300\n2000 expect cell_ov\n")
    detected = {}
    for side, source in (("host", ["--image", image]), ("twin", ["--elf", elf, "--image", image])):
        summary, _, _ = simulate(sim, scratch, f"{side}-{image}-step", path, 3000, source)
        events = [e for e in summary["protection_events"] if e["fault"] == "cell_ov"]
        if not events:
            fail(f"step on the grid: no cell_ov on the {side}")
        detected[side] = events[0]["detected_ms"]
        if not 2000.0 <= detected[side] < 2100.0:
            fail(f"step on the grid at 2000 ms: cell_ov detected at {detected[side]:.3f} ms on the {side}, not "
                 "by the scan of that tick")
    print(f"REPORT twin.{image}.agreement.step_on_grid: cell_ov detected {detected['host'] - 2000:.3f} ms (host) / "
          f"{detected['twin'] - 2000:.3f} ms (twin) after a step on the scan tick")


# Onset shifts of the intermittent link against the scan grid: on the grid, the first milliseconds after it
# (where a link window's edge falls inside a scan), and mid-period.
INTERMITTENT_SHIFTS_MS = [0, 1, 2, 3, 50]


def rate_episode(frames, onset, healed):
    """When comm_rate was first published after `onset` and first published cleared after `healed` (ms), and
    the PackSummaries between onset + 1 s and `healed` that do not carry it with the fault output asserted."""
    bit = 1 << FAULTS.index("comm_rate")
    ps = pack_summaries(frames)
    tripped = next((t for t, *_, faults in ps if t > onset and faults & bit), None)
    cleared = next((t for t, *_, faults in ps if t > healed and not faults & bit), None)
    gaps = [(t, faults) for t, _, _, out, _, faults in ps if onset + 1000 <= t <= healed and (not faults & bit or not out)]
    return tripped, cleared, gaps


def check_agreement_intermittent(sim, elf, image, scratch):
    """An intermittent link (most transactions failing for 3 s), its onset shifted against the scan grid: for
    every shift, on the host and on the twin alike, comm_rate is published within one second of the onset and
    held (with the fault output) until the link heals, and cleared within 2.5 s after it. When within that
    second it trips, and how often comm_loss and stale_data trip and clear meanwhile, may differ between the
    two (README: which scan attempts fail depends on where each transaction falls against the link's edges, to
    the microsecond), so the frames are not compared one by one as for ov-cell; the times are reported."""
    for shift in INTERMITTENT_SHIFTS_MS:
        onset, healed = 2000 + shift, 5000 + shift
        path = os.path.join(scratch, f"intermittent-{shift}.txt")
        with open(path, "w") as f:
            f.write(f"{onset} intermittent on\n{healed} intermittent off\n")
        results = {}
        for side, source in (("host", ["--image", image]), ("twin", ["--elf", elf, "--image", image])):
            summary, frames, _ = simulate(sim, scratch, f"{side}-{image}-intermittent", path, 7500, source)
            if side == "twin":
                check_healthy(summary)
            tripped, cleared, gaps = rate_episode(frames, onset, healed)
            if tripped is None or tripped > onset + 1000:
                fail(f"{side}, onset {onset} ms: comm_rate first published at {tripped} ms, not within 1 s")
            if gaps:
                fail(f"{side}, onset {onset} ms: PackSummary without comm_rate and the fault output at {gaps[:3]}")
            # Cleared once the monitor is back (a BQ769x set-up step that failed waits its 1 s retry interval)
            # and rateWindow (10) scans in a row validated: within 2.5 s of the healing.
            if cleared is None or cleared > healed + 2500:
                fail(f"{side}, onset {onset} ms: comm_rate cleared at {cleared} ms, the link healed at {healed} ms")
            results[side] = (tripped, cleared)
        (ht, hc), (tt, tc) = results["host"], results["twin"]
        print(f"REPORT twin.{image}.agreement.intermittent+{shift}ms: comm_rate published {ht - onset:.1f} ms "
              f"(host) / {tt - onset:.1f} ms (twin) after the onset, cleared {hc - healed:.1f} / {tc - healed:.1f} ms "
              "after the healing")


# Cells per board of each image (the top tap is the wire above the last one: open-wire <board> <cells + 1>).
CELLS = {"bq76952": 16, "bq76907": 7, "bq79616": 16, "bq4050": 4}


def check_open_wire_taps(sim, elf, image, scratch):
    """The sense wire at the bottom tap (below cell 1) and at the top tap (above the last cell) opens at 2 s: on
    the twin as on the host, open_wire is detected by the scan of that tick (its expect met, so bms-sim exits
    0), stays active, and no path is reported on (the readings beside an end tap are not cell voltages; before
    issue 24 a bottom tap went out as a valid 0 mV cell, with no fault)."""
    cells = CELLS[image.rsplit("-", 1)[1]]
    for tap in (1, cells + 1):
        path = os.path.join(scratch, f"open-wire-tap{tap}.txt")
        with open(path, "w") as f:
            f.write(f"2000 open-wire 0 {tap}\n2000 expect open_wire\n")
        detected = {}
        for side, source in (("host", ["--image", image]), ("twin", ["--elf", elf, "--image", image])):
            summary, _, _ = simulate(sim, scratch, f"{side}-{image}-tap{tap}", path, 3000, source)
            if "open_wire" not in summary["active_faults"]:
                fail(f"tap {tap} on the {side}: active faults {summary['active_faults']}, no open_wire")
            if summary["charge_on"] or summary["discharge_on"]:
                fail(f"tap {tap} on the {side}: a path is still reported on")
            events = [e for e in summary["protection_events"] if e["fault"] == "open_wire"]
            detected[side] = events[0]["detected_ms"]
            if not 2000.0 <= detected[side] < 2100.0:
                fail(f"tap {tap} on the {side}: open_wire detected at {detected[side]:.3f} ms, not by the scan at "
                     "2000 ms")
        print(f"REPORT twin.{image}.open_wire.tap{tap}: detected {detected['host'] - 2000:.3f} ms (host) / "
              f"{detected['twin'] - 2000:.3f} ms (twin) after the wire opened")


def check_slcan(sim, elf, image, scratch):
    text_path = os.path.join(scratch, f"{image}-twin.slcan")
    log = os.path.join(scratch, f"{image}-twin-slcan.log")
    summary, _ = run(sim, ["--elf", elf, "--image", image, "--scenario", "ov-cell", "--duration", "2500",
                           "--json", "--candump", log, "--slcan", text_path])
    parsed = read_slcan_text(text_path)
    logged = [(i, d) for _, i, d in read_candump(log)]
    if not parsed or parsed != logged or len(parsed) != summary["can_frames"]:
        fail(f"--slcan FILE has {len(parsed)} frames, --candump {len(logged)}, --json {summary['can_frames']}: "
             "they differ")
    print(f"REPORT twin.{image}.slcan_frames={len(parsed)} (--slcan FILE = --candump = --json)")


RECOVERY_MS = 500.0  # valid data again after a device fault ends (README "Device faults")
CAN_RESUME_MS = 250.0  # PackSummary again after error frames drove the controller bus-off


def recovery(frames, end_ms):
    """Milliseconds from end_ms to the first PackSummary from which on every one is valid without comm_loss,
    or None."""
    comm_loss = 1 << FAULTS.index("comm_loss")
    good = None
    for t, *_, valid, faults in pack_summaries(frames):
        ok = valid and not faults & comm_loss
        if ok and good is None:
            good = t
        elif not ok and t >= end_ms:
            good = None
    return None if good is None else max(0.0, good - end_ms)


def check_no_crystal(sim, elf, image, scratch):
    summary, _ = run(sim, ["--elf", elf, "--no-crystal", "--scenario", "idle", "--duration", "2000", "--json"])
    check_healthy(summary)
    if summary["can_frames"] != 0:
        fail(f"no crystal, no CAN clock: the image sent {summary['can_frames']} frames")
    # Scans every 100 ms from the end of the start-up (bring-up within a few hundred ms, a 64-device chain
    # excepted): at least 10 in 2 s, none failed.
    if summary["scans"] < 10 or summary["scan_failures"] != 0:
        fail(f"no crystal: {summary['scans']} scans, {summary['scan_failures']} failed in 2 s")
    print(f"REPORT twin.{image}.no-crystal: the HFXT wait ended; 2 s without a frame, a reset or a rule; "
          f"{summary['scans']} scans")


def check_faults(sim, elf, image, scratch):
    i2c = IMAGES[image].family != "bq79616"  # the BQ79616 chain is on a UART
    can = IMAGES[image].output == "can"
    # (name, steps, when the fault ends, duration): the device's own timeouts end the held lines (board.hpp).
    release = 1035 if IMAGES[image].family == "bq4050" else 3000
    cases = []
    if i2c:
        cases += [("stretch-within", "1000 stretch 1000\n2000 stretch 0\n", None, 3000),
                  ("stretch-beyond", "1000 stretch 50000\n2000 stretch 0\n", 2000, 3500),
                  ("stuck-scl", "1000 stuck-scl\n", release, release + 1500),
                  ("stuck-sda", "1000 stuck-sda\n", 1000, 2500)]
    else:
        cases += [("uart-noise", "1000 uart-noise 1000\n3000 uart-noise 0\n", 3000, 4500)]
    if can:
        cases += [("can-error-frames-passive", "1000 can-error-frames 20\n", None, 2500),
                  ("can-error-frames-bus-off", "1000 can-error-frames 40\n", 1000, 2500)]
    for name, steps, end, duration in cases:
        path = os.path.join(scratch, f"{image}-{name}.txt")
        with open(path, "w") as f:
            f.write(steps)
        for build, source in (("twin", ["--elf", elf, "--image", image]), ("host", ["--image", image])):
            summary, frames, _ = simulate(sim, scratch, f"{build}-{image}", path, duration, source)
            if build == "twin":
                check_healthy(summary)
            times = [s[0] for s in pack_summaries(frames)]
            gaps = [b - a for a, b in zip(times, times[1:])]
            start = first_valid(frames)
            if start is None:
                fail(f"{name} ({build}): never valid data")
            if end is None:
                # Nothing may be lost: every summary from the first valid one on is valid, none missing.
                lost = [s[0] for s in pack_summaries(frames) if s[0] > start and not s[4]]
                if lost or max(gaps) > 150.0:
                    fail(f"{name} ({build}): data not valid at {lost[:3]} ms, longest PackSummary gap "
                         f"{max(gaps):.1f} ms")
                print(f"REPORT twin.faults.{image}.{name}.{build}: nothing lost")
                continue
            if name.startswith("can-"):
                after = [t for t in times if t > end]
                resume = (after[0] - end) if after else None
                if resume is None or max(gaps) > CAN_RESUME_MS + 100.0:
                    fail(f"{name} ({build}): PackSummary stopped (longest gap {max(gaps):.1f} ms, bus-off "
                         f"{summary['bus_off']})")
                if not summary["bus_off"]:
                    fail(f"{name} ({build}): 40 error frames did not take the controller bus-off")
                print(f"REPORT twin.faults.{image}.{name}.{build}: bus-off at "
                      f"{summary['bus_off'][0]['at_ms']:.1f} ms, longest PackSummary gap {max(gaps):.1f} ms "
                      f"(bound {CAN_RESUME_MS + 100.0:.0f})")
                continue
            took = recovery(frames, end)
            if took is None or took > RECOVERY_MS:
                fail(f"{name} ({build}): valid data {took} ms after the fault ended at {end} ms "
                     f"(bound {RECOVERY_MS} ms)")
            print(f"REPORT twin.faults.{image}.{name}.{build}: valid again {took:.1f} ms after the fault "
                  f"ended at {end} ms (bound {RECOVERY_MS:.0f}); {summary['comm_errors']} comm errors")


def read_profile(path):
    """bsp/twin/profiler.hpp's format: key TAB value lines, exception and function rows."""
    keys, exceptions, functions = {}, [], []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            fields = line.rstrip("\n").split("\t")
            if fields[0] == "exception":
                n, name, entries, cycles, pct = fields[1:]
                exceptions.append((int(n), name, int(entries), int(cycles), float(pct)))
            elif fields[0] == "function":
                name, calls, cycles, pct, address, size = fields[1:]
                functions.append((name, int(calls), int(cycles), float(pct), int(address, 16), int(size)))
            elif len(fields) == 2:
                keys[fields[0]] = fields[1]
            else:
                fail(f"{path}: a line of no known kind: {line!r}")
    return keys, exceptions, functions


def check_profile(sim, elf, image, scratch):
    path = os.path.join(scratch, f"{image}.profile")
    result = subprocess.run([sim, "--image", image, "--profile", path], capture_output=True, text=True)
    if result.returncode != 2 or "--profile applies to --elf runs" not in result.stderr:
        fail(f"--profile without --elf: exit {result.returncode}, {result.stderr.strip()}")
    run(sim, ["--elf", elf, "--scenario", "idle", "--duration", "4000", "--json", "--profile", path])
    keys, exceptions, functions = read_profile(path)
    if keys.get("profile") != "1" or keys.get("image") != image or keys.get("clock_hz") != "32000000":
        fail(f"profile header: {keys}")
    busy, run_cycles, sleep = (int(keys[k]) for k in ("busy_cycles", "run_cycles", "sleep_cycles"))
    if run_cycles != 4000 * 32000 or busy + sleep != run_cycles or busy == 0:
        fail(f"run {run_cycles}, busy {busy}, sleep {sleep} cycles")
    if sum(e[3] for e in exceptions) != busy or sum(f[2] for f in functions) != busy:
        fail(f"the rows do not add up to the busy cycles {busy}: exceptions {sum(e[3] for e in exceptions)}, "
             f"functions {sum(f[2] for f in functions)}")
    if [f[2] for f in functions] != sorted((f[2] for f in functions), reverse=True):
        fail("function rows not in order of cycles")
    handler = "UART0_IRQHandler" if IMAGES[image].family == "bq79616" else "I2C0_IRQHandler"
    if not any(e[1] == handler and e[2] > 0 for e in exceptions):
        fail(f"{handler} never entered: {exceptions}")
    top = ", ".join(f"{f[0]} {f[3]:.1f} %" for f in functions[:10])
    print(f"REPORT twin.{image}.profile: busy {100.0 * busy / run_cycles:.2f} % of 4 s idle; top ten: {top}")


def main():
    if len(sys.argv) != 6:
        print(__doc__)
        return 2
    check, sim, dbc_dir, elf, scratch = sys.argv[1:]
    image = os.path.basename(elf)[:-len(".elf")]
    if not os.path.exists(elf):
        print(f"SKIP: {elf} is not built (./ci/test builds the images first)")
        return 77
    os.makedirs(scratch, exist_ok=True)
    if check == "ov-cell":
        check_ov_cell(sim, dbc_dir, elf, image, scratch)
    elif check == "comm-loss":
        check_comm_loss(sim, dbc_dir, elf, image, scratch)
    elif check == "bus-off":
        check_bus_off(sim, dbc_dir, elf, image, scratch)
    elif check == "agreement":
        check_agreement(sim, elf, image, scratch)
    elif check == "open-wire-taps":
        check_open_wire_taps(sim, elf, image, scratch)
    elif check == "agreement-intermittent":
        check_agreement_intermittent(sim, elf, image, scratch)
    elif check == "slcan":
        check_slcan(sim, elf, image, scratch)
    elif check == "load":
        check_load_paths(sim, image, scratch, ("--elf", elf))
    elif check == "options":
        check_options(sim, image, scratch, ("--elf", elf))
    elif check == "gauge-soc":
        check_gauge_soc(sim, scratch, ("--elf", elf))
    elif check == "profile":
        check_profile(sim, elf, image, scratch)
    elif check == "faults":
        check_faults(sim, elf, image, scratch)
    elif check == "no-crystal":
        check_no_crystal(sim, elf, image, scratch)
    elif check == "soc-count":
        check_soc_count(sim, image, scratch, ("--elf", elf), 300000)  # 5 minutes: the twin is slower than the host
    elif check == "storage":
        check_storage(sim, image, scratch, ("--elf", elf))
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
