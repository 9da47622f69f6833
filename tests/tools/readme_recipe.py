#!/usr/bin/python3
"""The README's python-can SLCAN recipe, run exactly as the README gives it, against the README's
`bms-sim --image lp-mspm0l1306-bq76952 --slcan pty` (with --duration 3000 instead of 60000, and --candump to
compare with). It once started with a 1.6 s burst (bms-sim had run while python-can slept after opening the
port) and ended in a traceback (bms-sim closed the terminal under the reader).

usage: readme_recipe.py <bms-sim> <repository> <scratch-dir>
Checks: the script and bms-sim exit 0 and print nothing on stderr but bms-sim's terminal line; the script prints
one line per frame bms-sim sent, with the frame's name from the DBC, in order; no line arrives more than 250 ms
ahead of the board's own timing (no burst); bms-sim ends once the script has closed the terminal, not on its
5 s bound. Prints a REPORT line."""
import os
import re
import subprocess
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bms_sim_acceptance import read_candump  # noqa: E402
import slcan_pty  # noqa: E402

NAMES = {0x100: "PackSummary", 0x101: "CellExtremes", 0x102: "TemperatureExtremes", 0x103: "ProtectionEvent",
         0x104: "StateOfCharge", 0x200: "CellVoltages", 0x201: "Temperatures", 0x202: "BalancingStatus"}  # bms.yaml


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def recipe(readme):
    """The script of the README's recipe (between <<'EOF' and EOF) and the bms-sim command it names."""
    text = open(readme).read()
    m = re.search(r"^/usr/bin/python3 - /dev/ttyACM0 <<'EOF'\n(.*?)^EOF$", text, re.S | re.M)
    if not m:
        fail("README.md has no python-can recipe (/usr/bin/python3 - /dev/ttyACM0 <<'EOF' ... EOF)")
    c = re.search(r"`\./build/host/bin/bms-sim (--image lp-mspm0l1306-bq76952 [^`]*--slcan pty)`", text)
    if not c:
        fail("README.md does not name the bms-sim command the recipe runs against")
    return m.group(1), c.group(1).split()


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    sim, repo, scratch = sys.argv[1:]
    os.makedirs(scratch, exist_ok=True)
    script, args = recipe(os.path.join(repo, "README.md"))
    args[args.index("--duration") + 1] = "3000"
    log = os.path.join(scratch, "readme-recipe.log")
    proc, path = slcan_pty.start(sim, *args, "--candump", log, stdout=subprocess.DEVNULL, cwd=repo)
    reader = subprocess.Popen(["/usr/bin/python3", "-", path], cwd=repo, stdin=subprocess.PIPE,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    reader.stdin.write(script)
    reader.stdin.close()
    lines, err = [], []
    drain = threading.Thread(target=lambda: err.append(reader.stderr.read()))
    drain.start()
    for line in reader.stdout:
        lines.append((time.monotonic(), line.rstrip("\n")))
    reader.wait(timeout=60)
    reader_end = time.monotonic()
    drain.join()
    sim_err = proc.stderr.read()
    proc.wait(timeout=30)
    sim_end = time.monotonic()
    if reader.returncode != 0 or err[0]:
        fail(f"the recipe exited {reader.returncode}, stderr: {err[0]!r}")
    if proc.returncode != 0 or sim_err:
        fail(f"bms-sim exited {proc.returncode}, stderr after its first line: {sim_err!r}")
    if sim_end - reader_end > 2.0:
        fail(f"bms-sim ended {sim_end - reader_end:.1f} s after the recipe closed the terminal (its bound, not "
             "the close)")
    frames = read_candump(log)
    if len(lines) != len(frames) or not frames:
        fail(f"the recipe printed {len(lines)} lines, bms-sim sent {len(frames)} frames")
    for (_, line), (_, ident, _) in zip(lines, frames):
        if line.split(" ")[0] != NAMES.get(ident):
            fail(f"frame {ident:03X} printed as {line!r}")
    # No burst: each line arrives at most 250 ms before the board's own time says (relative to the first).
    ahead = max((f[0] - frames[0][0]) / 1000.0 - (t - lines[0][0]) for (t, _), f in zip(lines, frames))
    if ahead > 0.25:
        fail(f"a line arrived {ahead:.2f} s ahead of the board's timing: a burst")
    # The first summary with data (the BQ76952's start-up, 130 ms, may outlast the first publish cycle).
    summary = next((l for _, l in lines if l.startswith("PackSummary") and "DataValid=1" in l), "none valid")
    # The recipe's image, L1306-BQ76952, builds the state of charge out (FW_SOC=0, README "Open questions").
    if "StateOfCharge=not_available" not in summary or "PackVoltage=59.2" not in summary:
        fail(f"PackSummary decodes as {summary!r}")
    print(f"REPORT readme.slcan_recipe: {len(lines)} frames printed, at most {max(ahead, 0) * 1000:.0f} ms ahead "
          f"of the board's timing, bms-sim ended {sim_end - reader_end:.2f} s after the recipe")
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
