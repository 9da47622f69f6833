#!/usr/bin/python3
"""bms-sim as a user runs it with bad scenario files and long runs (issue 15). Each case is one the tool
once crashed on, misread or went silent on.

usage: bms_sim_scenario_input.py <check> <bms-sim> <scratch-dir>
checks:
  bad-values   nan, inf, 1e308, fractions, 70000 mV, negative and huge times: exit 2 and one
               "file:line:col: error: ... <range>" line, no sanitizer report
  order        out-of-order steps run in time order with a warning naming the line (they used to block each
               other); a board the image lacks is a file:line:col error before the run
  drift        a value set on a drifting cell stays (the drift used to overwrite it), and a drift stops at
               the 5000 mV end of the range (it used to run past what the registers hold)
  expect       the `expect` scenario.hpp documents is accepted and measures the latency from its step; an expect
               that does not happen is reported as missed (text and --json) and the run exits 3 (it passed
               silently, exit 0)
  hostile-files  --elf and --scenario given a directory, /dev/zero or an oversize file: exit 2 with one clear
               line naming the file, promptly (--elf of a directory aborted, of /dev/zero grew without bound)
  long-run     --devices 64: the live view arrives while the run goes on (stdout a pipe, or with --json on
               stderr when it is a terminal), and no latency is negative ("fault before onset" instead)
Prints REPORT lines with what it measured."""
import json
import os
import pty
import re
import select
import subprocess
import sys
import time

IMAGE = "lp-mspm0g3507-bq79616"


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def scenario_file(scratch, name, text):
    path = os.path.join(scratch, name + ".txt")
    with open(path, "w") as f:
        f.write(text)
    return path


def run(sim, *args):
    return subprocess.run([sim, "--image", IMAGE, *args], capture_output=True, text=True, timeout=120)


def check_bad_values(sim, scratch):
    cases = [
        ("nan", "0 all-cells nan\n", 1, 13, "0..5000"),
        ("inf", "0 cell 0 2 inf\n", 1, 12, "0..5000"),
        ("huge", "0 temp 0 1 1e308\n", 1, 12, "2182..4232"),
        ("fraction", "0 current 1500.5\n", 1, 11, "-32768..32767"),
        ("wraps", "# 70000 mV read back as 4464 mV\n0 all-cells 70000\n", 2, 13, "0..5000"),
        ("ramp", "0 ramp-cell 0 2 nan\n", 1, 17, "-5000..5000"),
        ("negative-time", "0 bus-off\n-5 comm-loss on\n", 2, 1, "0..3600000"),
        ("huge-time", "4294968296 comm-loss on\n", 1, 1, "0..3600000"),
        ("float-time", "1e3 comm-loss on\n", 1, 1, "0..3600000"),
    ]
    for name, text, line, col, allowed in cases:
        path = scenario_file(scratch, name, text)
        r = run(sim, "--scenario", path, "--duration", "1500", "--json")
        if "runtime error" in r.stderr or "Sanitizer" in r.stderr:
            fail(f"{name}: sanitizer report: {r.stderr}")
        if r.returncode != 2:
            fail(f"{name}: exit {r.returncode}, not 2 (stdout {r.stdout[:200]!r})")
        first = r.stderr.splitlines()[0] if r.stderr else ""
        if not first.startswith(f"{path}:{line}:{col}: error: ") or allowed not in first:
            fail(f"{name}: expected '{path}:{line}:{col}: error: ... {allowed}', got {r.stderr!r}")
    print(f"REPORT sim.scenario.bad_values_rejected={len(cases)}")


def check_order(sim, scratch):
    path = scenario_file(scratch, "order", "3000 comm-loss on\n1000 all-cells 4300\n")
    r = run(sim, "--scenario", path, "--duration", "2000", "--json")
    if r.returncode != 0:
        fail(f"out of order: exit {r.returncode}: {r.stderr}")
    if not r.stderr.startswith(f"{path}:2:1: warning: ") or "line 1" not in r.stderr:
        fail(f"out of order: no warning naming line 2 and line 1: {r.stderr!r}")
    summary = json.loads(r.stdout)
    if summary["min_cell_mv"] != 4300 or summary["max_cell_mv"] != 4300:
        fail(f"the 1000 ms step did not run before the 3000 ms one: cells {summary['min_cell_mv']}.."
             f"{summary['max_cell_mv']} mV, not 4300")
    path = scenario_file(scratch, "board", "0 cell 0 2 3900\n100 ramp-cell 2 1 10\n")
    r = run(sim, "--devices", "2", "--scenario", path, "--json")
    if r.returncode != 2 or not r.stderr.startswith(f"{path}:2:15: error: board 2 does not exist"):
        fail(f"a board the image lacks: exit {r.returncode}, {r.stderr!r}")
    print("REPORT sim.scenario.out_of_order=sorted board_check=file:line:col")


def check_drift(sim, scratch):
    path = scenario_file(scratch, "drift-then-set", "0 ramp-cell 0 2 100\n1000 cell 0 2 3000\n")
    summary = json.loads(run(sim, "--scenario", path, "--duration", "2000", "--json").stdout)
    if (summary["min_cell_mv"], summary["max_cell_mv"]) != (3000, 3700):
        fail(f"cell 2 set to 3000 mV at 1 s while drifting: cells {summary['min_cell_mv']}.."
             f"{summary['max_cell_mv']} mV at 2 s, not 3000..3700")
    path = scenario_file(scratch, "drift-far", "0 ramp-all 5000\n")
    summary = json.loads(run(sim, "--scenario", path, "--duration", "3000", "--json").stdout)
    if summary["max_cell_mv"] != 5000:
        fail(f"a drift of 5000 mV/s for 3 s ends at {summary['max_cell_mv']} mV, not at the 5000 mV range end")
    print("REPORT sim.scenario.drift=replaced_by_set,stops_at_5000mV")


def check_expect(sim, scratch):
    path = scenario_file(scratch, "expect", "2000 comm-loss on\n2000 expect comm_loss\n")
    r = run(sim, "--scenario", path, "--duration", "3000", "--json")
    if r.returncode != 0:
        fail(f"expect: exit {r.returncode}: {r.stderr}")
    events = {e["fault"]: e for e in json.loads(r.stdout)["protection_events"]}
    e = events.get("comm_loss")
    if e is None or e["onset_ms"] != 2000.0 or e["latency_ms"] is None or e["latency_ms"] < 0:
        fail(f"comm_loss not measured from its expect at 2000 ms: {events}")
    if events.get("stale_data", {}).get("latency_note") != "no expected onset":
        fail(f"stale_data was not expected, yet: {events.get('stale_data')}")
    summary = json.loads(r.stdout)
    if summary["expects_missed"] != 0 or not summary["expects"][0]["met"]:
        fail(f"the comm_loss expect is not reported as met: {summary['expects']}")
    print(f"REPORT sim.scenario.expect_comm_loss_latency_ms={e['latency_ms']:.3f}")
    # Expects that never happen: a limit the pack never reaches, a fault that never comes, a step after the end.
    path = scenario_file(scratch, "missed",
                         "1000 expect otd 3332\n1000 expect comm_loss\n500 expect cell_ov\n9000 expect utd\n"
                         "500 all-cells 4300\n")
    for json_out in (True, False):
        r = run(sim, "--scenario", path, "--duration", "3000", *(["--json"] if json_out else []))
        if r.returncode != 3:
            fail(f"missed expects: exit {r.returncode}, not 3 ({r.stderr!r})")
        if json_out:
            summary = json.loads(r.stdout)
            got = {e["fault"]: (e["met"], e["missed"]) for e in summary["expects"]}
            want = {"otd": (False, "the pack never reached 3332 0.1 K"),
                    "comm_loss": (False, "no comm_loss event at or after the onset"),
                    "cell_ov": (True, None),
                    "utd": (False, "the run ended (3000 ms) before the step at 9000 ms")}
            if got != want or summary["expects_missed"] != 3:
                fail(f"missed expects in --json: {summary['expects']} ({summary['expects_missed']} missed)")
        else:
            missed = [l for l in r.stdout.splitlines() if "MISSED" in l]
            if len(missed) != 3 or "3 expect(s) missed" not in r.stdout:
                fail(f"missed expects in the text: {r.stdout[-600:]!r}")
    print("REPORT sim.scenario.missed_expects=3 of 4 reported, exit 3")


def check_hostile_files(sim, scratch):
    big = os.path.join(scratch, "big.elf")
    with open(big, "wb") as f:
        f.truncate(17 << 20)  # sparse: 17 MiB of zeros, over the 16 MiB an ELF may have
    big_text = os.path.join(scratch, "big.txt")
    with open(big_text, "w") as f:
        f.write("0 all-cells 3700\n" * 70000)  # 1.2 MB of valid steps, over the 1 MiB limit
    cases = [
        (["--elf", scratch], f"bms-sim: error: {scratch}: a directory, not a firmware ELF"),
        (["--elf", "/dev/zero"], "bms-sim: error: /dev/zero: not a regular file (a device or a pipe), not a firmware ELF"),
        (["--elf", big], f"bms-sim: error: {big}: larger than 16 MiB, which no firmware ELF needs"),
        (["--image", IMAGE, "--scenario", scratch], f"{scratch}: error: a directory, not a scenario file"),
        (["--image", IMAGE, "--scenario", "/dev/zero"],
         "/dev/zero: error: larger than 1 MiB, which no scenario file needs"),
        (["--image", IMAGE, "--scenario", big_text], f"{big_text}: error: larger than 1 MiB, which no scenario file needs"),
    ]
    for args, expect in cases:
        started = time.monotonic()
        r = subprocess.run([sim, *args, "--duration", "100"], capture_output=True, text=True, timeout=60)
        took = time.monotonic() - started
        if "runtime error" in r.stderr or "Sanitizer" in r.stderr or "terminate" in r.stderr:
            fail(f"{' '.join(args)}: {r.stderr!r}")
        if r.returncode != 2 or r.stderr != expect + "\n" or r.stdout:
            fail(f"{' '.join(args)}: exit {r.returncode}, stderr {r.stderr!r}, expected exit 2 and {expect!r}")
        if took > 10:
            fail(f"{' '.join(args)}: took {took:.1f} s")
    os.remove(big)
    print(f"REPORT sim.hostile_files={len(cases)} refused with one line and exit 2")


def arrivals(fd, proc):
    """Reads fd to its end; returns in which read() each live-view line arrived, by its t= value.

    A writer that flushes each line hands the reader one line per write; a block-buffered writer hands over
    everything at exit in one write. Counting reads, not wall-clock seconds, keeps the check independent of how
    fast this machine runs the simulation."""
    pending, seen, reads = b"", {}, 0
    while True:
        ready, _, _ = select.select([fd], [], [], 1.0)
        if not ready:
            if proc.poll() is not None:
                break
            continue
        try:
            chunk = os.read(fd, 65536)
        except OSError:  # a pty whose other side closed
            chunk = b""
        if not chunk:
            break
        reads += 1
        pending += chunk
        *lines, pending = pending.split(b"\n")
        for line in lines:
            m = re.match(rb"t=\s*([0-9.]+)s", line.strip())
            if m:
                seen[float(m.group(1))] = reads
    return seen


def spread(seen, label):
    """The live view must come while the run goes: the 0.5 s and 5.0 s lines in different reads.

    Buffered output (about 140 B a line, so 11 lines fit well inside one pipe write) would arrive in one read at
    exit; flushed lines arrive about 4.5 simulated seconds apart."""
    if 0.5 not in seen or 5.0 not in seen:
        fail(f"{label}: live lines missing: {sorted(seen)}")
    if seen[0.5] == seen[5.0]:
        fail(f"{label}: the live lines for 0.5 s and 5.0 s arrived in the same read: they were not flushed as "
             "the run went")
    return seen[5.0] - seen[0.5]


def check_long_run(sim, scratch):
    args = [sim, "--image", IMAGE, "--devices", "64", "--scenario", "ov-cell", "--duration", "5200"]
    # Plain output into a pipe.
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
    pipe_gap = spread(arrivals(proc.stdout.fileno(), proc), "stdout a pipe")
    proc.wait()
    # --json with stderr a terminal: progress there, and only the summary on stdout.
    master, slave = pty.openpty()
    proc = subprocess.Popen(args + ["--json"], stdout=subprocess.PIPE, stderr=slave)
    os.close(slave)
    tty_gap = spread(arrivals(master, proc), "--json, stderr a terminal")
    out, _ = proc.communicate(timeout=300)
    os.close(master)
    summary = json.loads(out)
    events = summary["protection_events"]
    for e in events:
        if e["latency_ms"] is not None and e["latency_ms"] < 0:
            fail(f"negative latency: {e}")
    ov = [e for e in events if e["fault"] == "cell_ov"]
    if not ov or ov[0]["latency_ms"] is None:
        fail(f"no cell_ov latency: {events}")
    notes = {e["fault"]: e["latency_note"] for e in events if e["latency_ms"] is None}
    print(f"REPORT sim.bq79616x64.live_view_reads_between_0.5s_and_5s pipe={pipe_gap} tty={tty_gap} "
          f"ov_cell_latency_ms={ov[0]['latency_ms']:.3f} unmeasured={notes}")


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    check, sim, scratch = sys.argv[1:4]
    os.makedirs(scratch, exist_ok=True)
    checks = {"bad-values": check_bad_values, "order": check_order, "drift": check_drift, "expect": check_expect,
              "long-run": check_long_run, "hostile-files": check_hostile_files}
    if check not in checks:
        print(__doc__)
        return 2
    checks[check](sim, scratch)
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
