#!/usr/bin/python3
"""Commands to the simulated boards as a user sends them (issue 27): python-can through `bms-sim --slcan pty`
both ways, scenario `send` steps on CAN, and the refusals. Frames are built here from the DBC (canmatrix) with
the CRC-8 SAE J1850 computed here, independently of the firmware and of bms-sim's own frame builder.

usage: bms_sim_commands.py <check> <bms-sim> <dbc-dir> <image-or-elf> <scratch-dir> [--elf]
checks:
  python-can  (L1306 images) python-can's slcan interface on --slcan pty: opens the channel, reads the
              published frames, tightens the discharge over-current limit, and drives the over-current the
              scenario's load causes three times (each recovered by a charge): a ClearFaults after the first
              (the load gone, not latched) is acknowledged and ends nothing before the recovery; the third
              latches the discharge path off through 4 s of charge (the charge path on); once the load has
              gone ClearFaults is acknowledged and the fault clears, the discharge path back on
  send        the same through scenario send steps (any image, host or --elf on the twin): the answers and
              the fault's trips, latch and clear in the published frames (the BQ4050 image: one output,
              so a load that stays retries every 3.2 s and the third trip latches; the BQ79616 image
              measures no current: a path request instead)
  refusals    bad CRC, repeated counter, wrong node, wrong length, out-of-range setting, an identifier that is
              not a command (CAN: rejected by the filter, no answer), a malformed SLCAN line (L1306)
  bmsctl      (L1306 images; the bmsctl path as sixth argument) bmsctl send against --slcan pty: identify,
              a setting read, a refused write (exit 1 and the reason), and a port with no board behind it
              (exit 3) or none at all (exit 4)
  flood       ov-cell with the bus (or line) full of valid commands from 1 s on: the protection latency, the
              PackSummary period and, on the twin, the CPU load; REPORT lines
  persist     (--elf, images with the record store) two runs on one `--flash FILE`: the first writes a
              setting and discharges 1.7 % from the open-circuit value; the second answers the setting from
              flash (SettingValue.Source flash) and starts from the kept state of charge (basis restored)
With --elf the fourth argument is the image's ELF (run on the MSPM0 twin); exit 77 when it is not built."""
import json
import os
import subprocess
import sys
import time

import canmatrix
import canmatrix.formats

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bms_sim_acceptance import fail, read_candump  # noqa: E402
import slcan_pty  # noqa: E402

ACK, PACK_SUMMARY, PROTECTION_EVENT = 0x580, 0x100, 0x103
OCD_BIT, OV_BIT = 1 << 3, 1 << 0
RESULTS = {0: "accepted", 1: "bad_crc", 2: "repeated_counter", 3: "wrong_length", 4: "out_of_range",
           5: "inconsistent", 6: "unsupported", 7: "wrong_key", 8: "paths_not_off", 9: "busy",
           10: "condition_present"}
# The discharge over-current latch (app/protection/default_limits.hpp): the third trip, each within 10 s of
# the one before, latches the discharge path off until ClearFaults finds the current gone. On the FET images
# each trip here is recovered by a charge of 1 A (3 s); the load of 25 A flows only while the DSG FET is on.
LATCH_SCENARIO = ("1000 current -25000\n2000 current 1000\n5500 current -25000\n6000 current 1000\n"
                  "9500 current -25000\n10000 current 1000\n14000 current 0\n")
LATCHED_FROM, LOAD_GONE = 10000, 14000
# The setup every check uses: the discharge over-current limit tightened from -30 A to -20 A (its clear value
# stays +200 mA: the fault recovers only while a charge flows, app/protection/default_limits.hpp).
SETTINGS = ["SettingWrite Setting=ocd_trip Value=-20000"]


def crc8_j1850(data):
    """CRC-8 SAE J1850: poly 0x1D, init 0xFF, final XOR 0xFF (check value 0x4B over b'123456789')."""
    crc = 0xFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


assert crc8_j1850(b"123456789") == 0x4B


class Commands:
    """Command frames from the DBC: Target 1, the next alive counter of the message, the CRC over the
    identifier (low byte, high byte) and payload bytes 1 .. DLC-1."""

    def __init__(self, dbc_dir):
        self.db = canmatrix.formats.loadp_flat(os.path.join(dbc_dir, "bms_native.dbc"))
        self.counters = {}

    def frame(self, name, **signals):
        f = self.db.frame_by_name(name)
        values = {s.name: 0 for s in f.signals}
        values["Target"] = 1
        values["Counter"] = self.counters.get(name, 0)
        self.counters[name] = (values["Counter"] + 1) % 16
        values.update(signals)
        data = bytearray(f.encode(values))
        ident = f.arbitration_id.id
        if "Crc" not in signals:
            data[0] = crc8_j1850(bytes([ident & 0xFF, ident >> 8]) + bytes(data[1:]))
        return ident, bytes(data)

    def decode(self, ident, data):
        f = self.db.frame_by_id(canmatrix.ArbitrationId(ident))
        return f.name, {k: v.raw_value for k, v in f.decode(bytearray(data)).items()}


def acks(frames):
    return [(t, Commands.decode_ack(d)) for t, i, d in frames if i == ACK]


def decode_ack(data):
    return {"command": data[1] | data[2] << 8, "counter": data[3] & 0xF, "result": RESULTS[data[4]],
            "rejected": data[5] | data[6] << 8}


Commands.decode_ack = staticmethod(decode_ack)


def active_faults(frames):
    """(ms, ActiveFaults) of every PackSummary."""
    return [(t, (d[6] | d[7] << 8) & 0x3FFF) for t, i, d in frames if i == PACK_SUMMARY]


def sim_args(target, elf):
    return ["--elf", target] if elf else ["--image", target]


def run_scenario(sim, target, elf, scratch, name, text, duration, extra=()):
    os.makedirs(scratch, exist_ok=True)
    scenario = os.path.join(scratch, f"{name}.scn")
    log = os.path.join(scratch, f"{name}.log")
    with open(scenario, "w") as f:
        f.write(text)
    started = time.monotonic()
    result = subprocess.run([sim, *sim_args(target, elf), "--scenario", scenario, "--duration", str(duration),
                             "--json", "--candump", log, *extra], capture_output=True, text=True)
    if result.returncode != 0:
        fail(f"bms-sim exited {result.returncode}: {result.stderr.strip()}")
    return json.loads(result.stdout), read_candump(log), time.monotonic() - started


def ocd_trips(frames):
    """The ms of each PackSummary in which the discharge over-current is newly active."""
    trips, before = [], 0
    for t, f in active_faults(frames):
        if f & OCD_BIT and not before:
            trips.append(t)
        before = f & OCD_BIT
    return trips


def check_latched_then_cleared(frames, first_clear_ms, latched_from, clear_ms):
    """Three trips, the first ClearFaults (not latched yet) ends nothing before the charge recovers it, the
    third trip held through the charge from latched_from (the charge path on, the discharge path off), and
    the ClearFaults at clear_ms, with the load gone, acknowledged and the fault cleared with the discharge path
    back on."""
    faults, fets = active_faults(frames), paths(frames)
    trips = ocd_trips(frames)
    if len(trips) != 3 or not trips[0] < first_clear_ms < trips[1] < latched_from:
        fail(f"expected three over-current trips, the first before {first_clear_ms} ms: {trips}")
    held = [f & OCD_BIT for t, f in faults if first_clear_ms < t < first_clear_ms + 500]
    if not held or not all(held):
        fail("the ClearFaults before the latch ended the over-current (a command overrode protection)")
    latched = [(f & OCD_BIT, c, d) for (t, f), (_, c, d) in zip(faults, fets) if latched_from + 500 < t < clear_ms]
    if not latched or any(l != (OCD_BIT, 1, 0) for l in latched):
        fail(f"the third over-current did not hold the discharge path alone off through the charge: {latched[:5]}")
    after = [(f & OCD_BIT, d) for (t, f), (_, c, d) in zip(faults, fets) if t > clear_ms + 300]
    if not after or any(a != (0, 1) for a in after):
        fail(f"after ClearFaults with the current gone the over-current is active or the DSG FET off: {after[:5]}")
    answers = [a for t, a in acks(frames)]
    clears = [a["result"] for a in answers if a["command"] == 0x600]
    if clears != ["accepted", "accepted"]:
        fail(f"ClearFaults was answered {clears}")
    return answers


def check_latch_one_output(frames, latched_from, clear_ms):
    """One fault output (BQ4050): a load that stays trips every 3.2 s; the third trip latches (no trip after
    it while the load stays), and ClearFaults once the load has gone releases the output."""
    trips = ocd_trips(frames)
    if len(trips) != 3 or trips[-1] > latched_from:
        fail(f"expected three over-current trips before {latched_from} ms: {trips}")
    faults, fets = active_faults(frames), paths(frames)
    held = [(f & OCD_BIT, c, d) for (t, f), (_, c, d) in zip(faults, fets) if latched_from < t < clear_ms]
    if not held or any(h != (OCD_BIT, 0, 0) for h in held):
        fail(f"the latched over-current did not hold the output: {held[:5]}")
    after = [(f & OCD_BIT, c, d) for (t, f), (_, c, d) in zip(faults, fets) if t > clear_ms + 300]
    if not after or any(a != (0, 1, 1) for a in after):
        fail(f"after ClearFaults the over-current is active or the output asserted: {after[:5]}")
    return [a for t, a in acks(frames)]


def paths(frames):
    """(ms, ChargeFet, DischargeFet) of every PackSummary (2 bits each from bit 40: 0 off, 1 on, 3 unknown)."""
    return [(t, d[5] & 3, (d[5] >> 2) & 3) for t, i, d in frames if i == PACK_SUMMARY]


def check_send_without_current(sim, target, scratch, elf):
    """The BQ79616 image measures no current (no over-current to latch): a held-off path and its release."""
    text = "1000 send PathRequest DischargeOff=hold_off\n2000 send PathRequest DischargeOff=release\n"
    text += "2500 send ClearFaults\n"
    summary, frames, seconds = run_scenario(sim, target, elf, scratch, "send", text, 3500)
    held = [d for t, c, d in paths(frames) if 1300 < t < 2000]
    released = [c == 1 and d == 1 for t, c, d in paths(frames) if t > 2300]
    if not held or any(held) or not released or not all(released):
        fail(f"the fault output did not follow the path request: {paths(frames)}")
    answers = [a["result"] for t, a in acks(frames)]
    if answers != ["accepted"] * 3:
        fail(f"answers {answers}")
    print(f"REPORT commands.{summary['image']}{'.twin' if elf else ''}.send: a discharge path held off and "
          f"released by PathRequest (the fault output), {len(answers)} answers accepted ({seconds:.1f} s)")


def check_send(sim, dbc_dir, target, scratch, elf):
    if "bq79616" in target:
        return check_send_without_current(sim, target, scratch, elf)
    text = "".join(f"{500 + 100 * k} send {s}\n" for k, s in enumerate(SETTINGS))
    if "bq4050" in target:  # one output: the load stays, retried every 3.2 s, then gone once latched
        text += "1000 current -25000\n13000 current 0\n13500 send ClearFaults\n"
        summary, frames, seconds = run_scenario(sim, target, elf, scratch, "send", text, 15000)
        answers = check_latch_one_output(frames, 8000, 13500)
    else:
        text += LATCH_SCENARIO + f"1500 send ClearFaults\n{LOAD_GONE + 500} send ClearFaults\n"
        summary, frames, seconds = run_scenario(sim, target, elf, scratch, "send", text, LOAD_GONE + 2000)
        answers = check_latched_then_cleared(frames, 1500, LATCHED_FROM, LOAD_GONE + 500)
    if [a["result"] for a in answers] != ["accepted"] * len(answers) or len(answers) != len(SETTINGS) + \
            (1 if "bq4050" in target else 2):
        fail(f"answers {answers}")
    if summary["active_faults"] or not summary["discharge_on"]:
        fail(f"the run ends with {summary['active_faults']}, discharge_on {summary['discharge_on']}")
    print(f"REPORT commands.{summary['image']}{'.twin' if elf else ''}.send: ocd tripped 3 times and latched, "
          f"ClearFaults with the load gone cleared it, {len(answers)} answers accepted ({seconds:.1f} s)")


def check_refusals(sim, dbc_dir, target, scratch, elf):
    steps = [
        "send SettingRead Setting=cell_ov_trip Crc=0",         # bad CRC
        "send SettingRead Setting=cell_ov_trip Counter=9",     # taken
        "send SettingRead Setting=cell_ov_trip Counter=9",     # repeated counter
        "send ClearFaults Target=7",                           # another node: no answer
        "send SettingWrite Setting=ocd_trip Value=-50000",     # past the hard bound
        "send SettingWrite Setting=12 Value=0",                # no such setting
        "send EnterBootloader TraceId=0 Key=key",              # not this chip
        "send ProtectionEvent",                                # not a command (CAN: the filter)
    ]
    text = "".join(f"{1000 + 50 * k} {s}\n" for k, s in enumerate(steps))
    summary, frames, _ = run_scenario(sim, target, elf, scratch, "refusals", text, 2000)
    if elf and summary.get("twin_warnings"):  # e.g. MCAN-FILTER-OPEN at the non-command, as twin_images.py
        fail(f"the twin noticed: {summary['twin_warnings']}")
    got = [(a["command"], a["result"]) for t, a in acks(frames)]
    want = [(0x604, "bad_crc"), (0x604, "accepted"), (0x604, "repeated_counter"), (0x605, "out_of_range"),
            (0x605, "out_of_range"), (0x606, "wrong_key")]
    if got != want:
        fail(f"answers {got}, expected {want}")
    rejected = [a["rejected"] for t, a in acks(frames)][-1]
    if rejected != 5:
        fail(f"the last answer counts {rejected} refusals, not 5")
    if summary["active_faults"] or not (summary["charge_on"] and summary["discharge_on"]):
        fail("a refused command changed the paths or the faults")
    print(f"REPORT commands.{summary['image']}{'.twin' if elf else ''}.refusals: {len(got)} answers as "
          f"expected, the other node's frame and the non-command unanswered")


def check_flood(sim, dbc_dir, target, scratch, elf):
    # ov-cell (cell 2 drifts past 4.25 V from 1 s) with valid Identify commands back to back from 1 s: each is
    # answered with three frames, so the answers alone would fill the bus.
    text = ("0 current 5000\n0 cell 0 2 4200\n1000 ramp-cell 0 2 40\n1000 expect cell_ov 4250\n"
            "1000 flood 5000 Identify\n")
    summary, frames, seconds = run_scenario(sim, target, elf, scratch, "flood", text, 6000)
    events = [e for e in summary["protection_events"] if e["fault"] == "cell_ov"]
    if not events or events[0]["latency_ms"] is None:
        fail(f"no cell_ov latency under the flood: {summary['protection_events']}")
    latency = events[0]["latency_ms"]
    # The README's budget: scan period + the image's scan time (tick to evaluation) + 2 ms.
    scan_ms = {"bq76952": 2.0, "bq76907": 1.2, "bq4050": 30.2, "bq79616": 2.2}[summary["image"].split("-")[-1]]
    budget = 100 + scan_ms + 2
    if latency > budget:
        fail(f"cell_ov latency {latency} ms under the flood, budget {budget} ms")
    summaries = [t for t, i, d in frames if i == PACK_SUMMARY and 1000 < t < 6000]
    worst_gap = max(b - a for a, b in zip(summaries, summaries[1:]))
    if worst_gap > 110:
        fail(f"PackSummary went {worst_gap:.1f} ms without a frame under the flood")
    answered = sum(1 for t, i, d in frames if i == ACK)
    extra = ""
    if elf:
        extra = (f", twin CPU load {summary['cpu_load_pct']} % (longest ISR {summary['isr_max_us']} us, worst "
                 f"interrupt latency {summary['wake_latency_max_us']} us)")
    print(f"REPORT commands.{summary['image']}{'.twin' if elf else ''}.flood: cell_ov latency {latency:.1f} ms "
          f"(budget {budget:.1f} ms), PackSummary every {worst_gap:.1f} ms at worst, {answered} commands "
          f"answered in 5 s of a full {'line' if 'l1306' in summary['image'] else 'bus'}{extra}")


def check_python_can(sim, dbc_dir, image, scratch):
    import can  # python3-can (Debian)

    cmd = Commands(dbc_dir)
    os.makedirs(scratch, exist_ok=True)
    scenario = os.path.join(scratch, "python-can.scn")
    with open(scenario, "w") as f:
        f.write(LATCH_SCENARIO)
    log = os.path.join(scratch, "python-can.log")
    proc, path = slcan_pty.start(sim, "--image", image, "--duration", str(LOAD_GONE + 2000), "--slcan", "pty",
                                 "--json", "--scenario", scenario, "--candump", log)
    bus = slcan_pty.open_bus(path)
    received, answers, marks, trips, stage = [], [], {}, 0, "settings"
    ocd_before, charged_while_latched = False, 0

    def send_clear(name):
        ident, data = cmd.frame("ClearFaults")
        bus.send(can.Message(arbitration_id=ident, data=data, is_extended_id=False))
        marks[name] = len(received)

    start = time.monotonic()
    try:
        while proc.poll() is None and time.monotonic() - start < 60:
            try:
                msg = bus.recv(timeout=0.2)
            except can.CanError:
                break
            if msg is None:
                continue
            received.append((msg.arbitration_id, bytes(msg.data)))
            if msg.arbitration_id == ACK:
                answers.append(decode_ack(msg.data))
            if msg.arbitration_id != PACK_SUMMARY:
                continue
            current = int.from_bytes(msg.data[2:4], "little", signed=True)
            ocd = bool((msg.data[6] | msg.data[7] << 8) & OCD_BIT)
            trips += ocd and not ocd_before
            ocd_before = ocd
            if stage == "settings":
                for s in SETTINGS:
                    name, *words = s.split()
                    fields = {k: int(v) if v.lstrip("-").isdigit() else v for k, v in (w.split("=") for w in words)}
                    fields["Setting"] = {"ocd_trip": 6}[fields["Setting"]]
                    ident, data = cmd.frame(name, **fields)
                    bus.send(can.Message(arbitration_id=ident, data=data, is_extended_id=False))
                stage = "first trip"
            elif stage == "first trip" and ocd and current == 0:
                send_clear("first")  # the load no longer flows (DSG off); not latched: its recovery stands
                stage = "latching"
            elif stage == "latching" and trips == 3:
                stage = "latched"
            elif stage == "latched" and ocd and current > 0:
                charged_while_latched += 1
            elif stage == "latched" and ocd and current == 0 and charged_while_latched:
                send_clear("latched")  # the charger and the load gone: the current is gone
                stage = "cleared"
    finally:
        try:
            bus.shutdown()
        except can.CanError:
            pass
    out, err = proc.communicate(timeout=30)
    if proc.returncode != 0:
        fail(f"bms-sim --slcan pty exited {proc.returncode}: {err}")
    if stage != "cleared":
        fail(f"the scenario never reached the latched over-current with the current gone (stage: {stage}, "
             f"{trips} trips)")
    if trips != 3:
        fail(f"{trips} over-current trips, expected 3")
    if [a["result"] for a in answers] != ["accepted"] * 3 or [a["command"] for a in answers[1:]] != [0x600] * 2:
        fail(f"python-can read the answers {answers}")
    summaries = [(k, d) for k, (i, d) in enumerate(received) if i == PACK_SUMMARY]
    # The first clear: the over-current stays while the current is gone, until the charge recovers it.
    later = [d for k, d in summaries if k > marks["first"]]
    idle = later[:next((n for n, d in enumerate(later) if int.from_bytes(d[2:4], "little", signed=True) > 0), 0)]
    if not idle or not all((d[6] | d[7] << 8) & OCD_BIT for d in idle):
        fail("ClearFaults ended the unlatched over-current before its recovery (a command overrode protection)")
    # Latched: held through 3 s of charge or more, the charge path on and the discharge path off.
    if charged_while_latched < 30:
        fail(f"the latched over-current was seen through only {charged_while_latched} summaries of charge")
    held = [((d[6] | d[7] << 8) & OCD_BIT, d[5] & 3, (d[5] >> 2) & 3) for k, d in summaries
            if int.from_bytes(d[2:4], "little", signed=True) > 0 and k < marks["latched"]][-30:]
    if any(h != (OCD_BIT, 1, 0) for h in held):
        fail(f"while latched the paths were not charge on, discharge off: {held}")
    after = [d for k, d in summaries if k > marks["latched"]]
    if not after or (after[-1][6] | after[-1][7] << 8) & OCD_BIT or (after[-1][5] >> 2) & 3 != 1:
        fail("after ClearFaults with the current gone the over-current is still active or the discharge path off")
    summary = json.loads(out)
    if summary["active_faults"]:
        fail(f"the run ends with {summary['active_faults']}")
    print(f"REPORT commands.{image}.python_can: {len(received)} frames read, 3 commands sent and acknowledged; "
          f"ocd tripped 3 times, the third latched through {charged_while_latched} summaries of charge, and "
          f"ClearFaults with the current gone cleared it (python-can slcan over --slcan pty)")


def check_bmsctl(sim, image, scratch, bmsctl):
    proc, path = slcan_pty.start(sim, "--image", image, "--duration", "6000", "--slcan", "pty", "--json")

    def send(*args, timeout=2000):
        r = subprocess.run([bmsctl, "send", "--port", path, "--timeout", str(timeout), *args], capture_output=True,
                           text=True)
        return r.returncode, r.stdout, r.stderr

    try:
        rc, out, err = send("identify")
        lines = out.splitlines()
        if rc != 0 or len(lines) != 3 or not lines[0].startswith("CommandAck Node=1 Command=0x603") or \
                "Result=accepted" not in lines[0] or not lines[1].startswith("IdentifyVersion") or \
                "Image=lp_mspm0l1306" not in lines[1] or "TraceId=0x5A5A1306" not in lines[2]:
            fail(f"bmsctl send identify: exit {rc}, {out!r} {err!r}")
        rc, out, err = send("setting-read", "Setting=ocd_trip")
        if rc != 0 or "SettingValue Node=1 Setting=ocd_trip Unit=mA Value=-30000" not in out or \
                "SettingRange Node=1 Setting=ocd_trip Min=-30000 Max=-100" not in out:
            fail(f"bmsctl send setting-read: exit {rc}, {out!r} {err!r}")
        rc, out, err = send("SettingWrite", "Setting=ocd_trip", "Value=-50000")
        if rc != 1 or "refused" not in err or "Result=out_of_range" not in err:
            fail(f"bmsctl send of an out-of-range setting: exit {rc}, {out!r} {err!r}")
        rc, out, err = send("no-such-command")
        if rc != 2 or "unknown command 'no-such-command'" not in err:
            fail(f"bmsctl send no-such-command: exit {rc}, {err!r}")
    finally:
        proc.kill()
        proc.communicate()
    master, slave = os.openpty()  # a serial port with nothing behind it
    try:
        started = time.monotonic()
        r = subprocess.run([bmsctl, "send", "--port", os.ttyname(slave), "--timeout", "300", "identify"],
                           capture_output=True, text=True)
        if r.returncode != 3 or "no answer" not in r.stderr or time.monotonic() - started > 5:
            fail(f"bmsctl send to a silent port: exit {r.returncode}, {r.stderr!r}")
    finally:
        os.close(master)
        os.close(slave)
    r = subprocess.run([bmsctl, "send", "--port", "/dev/no-such-port", "identify"], capture_output=True, text=True)
    if r.returncode != 4 or "cannot open /dev/no-such-port" not in r.stderr:
        fail(f"bmsctl send to a missing port: exit {r.returncode}, {r.stderr!r}")
    print(f"REPORT commands.{image}.bmsctl: identify, setting-read and a refused write through --slcan pty; "
          f"exit 3 on a silent port, 4 on a missing one")


SETTING_VALUE = 0x583
SOURCES = {0: "default", 1: "flash", 2: "command", 3: "flash_refused"}


def setting_values(frames):
    """(setting, value, source) of every SettingValue answer."""
    return [(d[1], int.from_bytes(d[3:7], "little", signed=True), SOURCES[d[7]])
            for t, i, d in frames if i == SETTING_VALUE]


def check_persist(sim, dbc_dir, target, scratch, elf):
    if not elf:
        fail("persist: the host boards build no record store; run it on the twin (--elf)")
    flash = os.path.join(scratch, "flash.bin")
    if os.path.exists(flash):
        os.remove(flash)  # a blank region: created erased by the first run
    # Run 1: the open-circuit value at the first scans, then a command's write, then 15 A for 6 s: 25 mAh,
    # 1 % of the EVM pack's 2 500 mAh (firmware/app/packs/bq76952-evm.yaml), so the kept value moves on.
    text = ("0 current 0\n1000 send SettingWrite Setting=ocd_trip Value=-20000\n1500 current -15000\n"
            "8000 current 0\n8500 send SettingRead Setting=ocd_trip\n")
    first, frames, _ = run_scenario(sim, target, elf, scratch, "persist-1", text, 9000, ("--flash", flash))
    got = setting_values(frames)
    if got != [(6, -20000, "command")]:
        fail(f"persist: the first run answered {got}, expected ocd_trip -20000 from the command")
    if first["soc_basis"] != "ocv" or first["state_of_charge_permille"] is None:
        fail(f"persist: the first run's state of charge: {first['state_of_charge_permille']} "
             f"({first['soc_basis']}), expected a counted one from the open-circuit table")
    # Run 2, a power-on with the same flash: the setting from flash, the state of charge from the last record
    # (written at each 1 % step: within 1 % of where the first run ended).
    text = "500 send SettingRead Setting=ocd_trip\n500 send SettingRead Setting=ocd_clear\n"
    second, frames, _ = run_scenario(sim, target, elf, scratch, "persist-2", text, 1500, ("--flash", flash))
    got = setting_values(frames)
    if len(got) != 2 or got[0] != (6, -20000, "flash") or got[1][2] != "flash":
        fail(f"persist: the second run answered {got}, expected ocd_trip -20000 and ocd_clear from flash")
    p1, p2 = first["state_of_charge_permille"], second["state_of_charge_permille"]
    if second["soc_basis"] != "restored" or p2 is None or abs(p2 - p1) >= 10:
        fail(f"persist: the second run starts from {p2} permille ({second['soc_basis']}), expected the first "
             f"run's {p1} restored (within the 1 % step)")
    print(f"REPORT commands.{first['image']}.twin.persist: run 1 ocd_trip -20000 by command, state of charge "
          f"{p1} permille (ocv, counted); run 2 on the same --flash: ocd_trip {got[0][1]} from {got[0][2]}, "
          f"state of charge {p2} permille ({second['soc_basis']})")


def main():
    if len(sys.argv) < 6:
        print(__doc__)
        return 2
    check, sim, dbc_dir, target, scratch = sys.argv[1:6]
    elf = "--elf" in sys.argv[6:]
    if check == "bmsctl" and len(sys.argv) < 7:
        print(__doc__)
        return 2
    if elf and not os.path.exists(target):
        print(f"SKIP: {target} is not built")
        return 77
    os.makedirs(scratch, exist_ok=True)
    if check == "python-can":
        check_python_can(sim, dbc_dir, target, scratch)
    elif check == "send":
        check_send(sim, dbc_dir, target, scratch, elf)
    elif check == "refusals":
        check_refusals(sim, dbc_dir, target, scratch, elf)
    elif check == "flood":
        check_flood(sim, dbc_dir, target, scratch, elf)
    elif check == "bmsctl":
        check_bmsctl(sim, target, scratch, sys.argv[6])
    elif check == "persist":
        check_persist(sim, dbc_dir, target, scratch, elf)
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
