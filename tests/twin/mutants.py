#!/usr/bin/python3
"""Mutation run of bsp/mspm0 on the MSPM0 twin: how many realistic silicon bugs the twin catches, and whether it
names the cause.

usage: mutants.py [--list] [--only NAME[,NAME...]] [--jobs 1|2] [--scratch DIR] [--json FILE] [--markdown FILE]

Each mutant of tests/twin/mutants_table.py is one source edit in bsp/mspm0. For each, the edit is applied to a
scratch copy of the tree (<repo>/build/mutants/slot<N>: the working tree without build/ and .git, copied once;
the edit is undone after the mutant), the affected image presets are built there (their own build directories,
kept between mutants, so a mutant costs one compile and one link; the compiler launcher of the environment is
used, e.g. CMAKE_CXX_COMPILER_LAUNCHER=ccache), and each image runs on the twin through the repository's
bms-sim (build/host/bin/bms-sim, the host preset):
  - a probe: bms-sim --elf IMAGE --scenario ov-cell --duration 4000 --json --candump (how the run ended, resets
    and their causes from the Startup frames, HardFaults, the twin's warnings);
  - the twin checks of tests/twin/twin_images.py: ov-cell, comm-loss, agreement, faults, and slcan (L1306) or
    bus-off and no-crystal (G3507); and tests/tools/bms_sim_commands.py send and refusals (the commands reach the image).
The unmutated images run the same checks first; a check that fails there is left out for that image.

Verdicts:
  named    the twin said why: a rule ([WIRE-...], [PIN-INENA], [RACE-ISR-RMW], ...) stopped the run or warned,
           the twin stopped with a reason (an access no model covers, a full FIFO, ...), a HardFault, or a reset
           whose cause the image published (Startup: watchdog, or the fault record's module and line)
  unnamed  only a check failed (e.g. never valid data, a period off)
  missed   every check passed and the twin reported nothing
  build    the mutant does not compile or link (the compiler caught it: not counted as a twin catch)
The twin's catch rate is (named + unnamed) / (mutants that built); the named rate is named / that.

--list validates the table against the current tree (every original text occurs exactly once in its file; exit 1
otherwise) and prints it; nothing is built. The ctest twin.mutants.table runs it.
Exit status: 0 the run completed (whatever the verdicts), 1 a bad table or a baseline image that does not build,
2 bad arguments."""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
from mutants_table import MUTANTS  # noqa: E402

sys.path.insert(0, os.path.dirname(HERE))
import image_descriptions  # noqa: E402  (tests/image_descriptions.py)

SIM = os.path.join(ROOT, "build", "host", "bin", "bms-sim")
REGMAPGEN = os.path.join(ROOT, "build", "host", "bin", "regmapgen")
DBC = os.path.join(ROOT, "firmware", "app", "can")
TWIN_CHECKS = os.path.join(ROOT, "tests", "twin", "twin_images.py")
COMMAND_CHECKS = os.path.join(ROOT, "tests", "tools", "bms_sim_commands.py")
PYTHON = "/usr/bin/python3"  # Debian's: it sees python3-canmatrix, as the ctest entries use
CHECK_TIMEOUT_S = 300
STARTUP = 0x1F0
# bms.yaml Startup.ResetCause values the probe names.
RESET_CAUSES = {1: "power-on", 13: "software BOOTRST", 14: "watchdog (WWDT0)", 16: "BSL exit", 17: "BSL entry",
                21: "CPU lockup", 27: "software SYSRST", 29: "CPU software reset"}
MODULES = {1: "core", 2: "sched", 3: "hal", 10: "bq769x2", 11: "bq79616", 12: "bq4050", 20: "app",
           21: "protection", 22: "publish", 30: "bsp", 31: "bsp i2c", 32: "bsp uart", 33: "bsp can"}
RULE = re.compile(r"\[([A-Z0-9]+(?:-[A-Z0-9]+)+)\]")


def checks_for(image):
    twin = ["ov-cell", "comm-loss", "agreement", "faults"]
    can = image_descriptions.by_preset()[image].output != "slcan"
    twin += ["bus-off", "no-crystal"] if can else ["slcan"]
    return [("twin", c) for c in twin] + [("commands", c) for c in ("send", "refusals")]


def validate(mutants, root):
    """The table's problems against the tree at `root` (empty when every entry applies)."""
    problems, names = [], set()
    for m in mutants:
        for key in ("name", "kind", "file", "original", "replacement", "images", "board"):
            if key not in m:
                problems.append(f"{m.get('name', '?')}: no '{key}'")
        if m["name"] in names:
            problems.append(f"{m['name']}: name used twice")
        names.add(m["name"])
        path = os.path.join(root, m["file"])
        if not m["file"].startswith("bsp/mspm0/"):
            problems.append(f"{m['name']}: {m['file']} is not in bsp/mspm0")
        if not os.path.exists(path):
            problems.append(f"{m['name']}: {m['file']} does not exist")
            continue
        with open(path) as f:
            count = f.read().count(m["original"])
        if count != 1:
            problems.append(f"{m['name']}: the original text occurs {count} times in {m['file']} (must be once)")
        if m["original"] == m["replacement"]:
            problems.append(f"{m['name']}: the replacement is the original")
        if not 1 <= len(m["images"]) <= 2:
            problems.append(f"{m['name']}: 1 or 2 images, not {len(m['images'])}")
    return problems


class Slot:
    """One scratch copy of the tree with its own image build directories."""

    def __init__(self, path, build_jobs, log):
        self.path = path
        self.build_jobs = build_jobs
        self.log = log
        self.configured = set()

    def sync(self):
        """Copies the working tree as it is (tracked and untracked files, what --list validated; no build outputs)
        where it differs, with a new modification time, so the slot's builds stay incremental."""
        listed = subprocess.run(["git", "ls-files", "-co", "--exclude-standard", "-z"], cwd=ROOT, check=True,
                                capture_output=True).stdout.decode().split("\0")
        for rel in filter(None, listed):
            source, target = os.path.join(ROOT, rel), os.path.join(self.path, rel)
            if not os.path.isfile(source):
                continue  # deleted in the working tree
            with open(source, "rb") as f:
                data = f.read()
            if os.path.exists(target):
                with open(target, "rb") as f:
                    if f.read() == data:
                        continue
            os.makedirs(os.path.dirname(target), exist_ok=True)
            shutil.copyfile(source, target)
            shutil.copymode(source, target)

    def build(self, image):
        """(ok, output tail)."""
        if image not in self.configured:
            r = subprocess.run(["cmake", "--preset", image, f"-DBMS_REGMAPGEN={REGMAPGEN}"], cwd=self.path,
                               capture_output=True, text=True)
            if r.returncode != 0:
                return False, (r.stdout + r.stderr)[-2000:]
            self.configured.add(image)
        r = subprocess.run(["cmake", "--build", os.path.join("build", image), "-j", str(self.build_jobs)],
                           cwd=self.path, capture_output=True, text=True)
        return r.returncode == 0, (r.stdout + r.stderr)[-3000:]

    def elf(self, image):
        return os.path.join(self.path, "build", image, f"{image}.elf")


def startup_frames(log):
    """(ms since the run started, data) of each Startup frame in a candump log."""
    sys.path.insert(0, os.path.join(ROOT, "tests", "tools"))
    from bms_sim_acceptance import read_candump  # imported here: --list needs no canmatrix
    return [(t, d) for t, ident, d in read_candump(log) if ident == STARTUP]


def probe(elf, scratch):
    """The twin's own account of a 4 s ov-cell run: a list of named causes and the JSON (or None)."""
    log = os.path.join(scratch, "probe.log")
    if os.path.exists(log):
        os.remove(log)
    try:
        r = subprocess.run([SIM, "--elf", elf, "--scenario", "ov-cell", "--duration", "4000", "--json",
                            "--candump", log], capture_output=True, text=True, timeout=CHECK_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return ["probe: bms-sim did not finish within 300 s"], None
    causes = []
    stop = re.search(r"the twin stopped: (.*)", r.stderr)
    if stop:
        causes.append("stop: " + stop.group(1).strip())
    elif r.returncode not in (0, 1, 3):  # 3: a scenario expect missed, a check's finding, not a cause
        causes.append(f"bms-sim exit {r.returncode}: {r.stderr.strip()[:200]}")
    summary = None
    try:
        summary = json.loads(r.stdout)
    except ValueError:
        pass
    if summary:
        if int(summary.get("twin_hard_faults", 0)):
            causes.append(f"{summary['twin_hard_faults']} HardFault(s)")
        warnings = summary.get("twin_warnings") or []
        for w in warnings:
            causes.append("warning: " + w)
        resets = int(summary.get("twin_resets", 0))
        if resets and os.path.exists(log):
            seen = []
            for t, d in startup_frames(log)[1:]:  # the first is the power-on
                cause = RESET_CAUSES.get(d[0], f"cause {d[0]}") if d else "?"
                if len(d) >= 7 and d[4] != 255:
                    line = int.from_bytes(d[5:7], "little")
                    cause += f", fault record {MODULES.get(d[4], d[4])} line 0x{line:04X}"
                seen.append(f"{cause} at {t:.0f} ms")
            if seen:
                causes.append(f"{resets} reset(s): " + "; ".join(seen[:3]))
            else:
                causes.append(f"{resets} reset(s), no Startup frame after them")
    return causes, summary


def run_check(kind, check, elf, scratch):
    """(passed, first line of the failure)."""
    work = os.path.join(scratch, f"{kind}-{check}")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    script = TWIN_CHECKS if kind == "twin" else COMMAND_CHECKS
    args = [PYTHON, script, check, SIM, DBC, elf, work] + (["--elf"] if kind == "commands" else [])
    try:
        r = subprocess.run(args, capture_output=True, text=True, timeout=CHECK_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return False, f"{check}: no result within {CHECK_TIMEOUT_S} s"
    if r.returncode == 0:
        return True, ""
    text = (r.stdout + r.stderr).strip().splitlines()
    fails = [ln for ln in text if ln.startswith("FAIL")] or text[-1:] or [f"exit {r.returncode}"]
    return False, f"{check}: {fails[0][:400]}"


def judge(elf, image, scratch, skip):
    """(verdict, causes, failures) of one image on the twin."""
    os.makedirs(scratch, exist_ok=True)
    causes, _ = probe(elf, scratch)
    failures = []
    for kind, check in checks_for(image):
        if (kind, check) in skip:
            continue
        ok, why = run_check(kind, check, elf, scratch)
        if not ok:
            failures.append(why)
            for rule in RULE.findall(why):
                text = f"rule [{rule}]"
                if not any(rule in c for c in causes):
                    causes.append(text)
            stop = re.search(r"the twin stopped: (.*)", why)
            if stop and not any(c.startswith("stop:") for c in causes):
                causes.append("stop: " + stop.group(1).strip())
    if causes:
        return "named", causes, failures
    return ("unnamed" if failures else "missed"), causes, failures


def apply(slot, mutant):
    """Edits the slot's copy; returns the file's text before, for restore()."""
    path = os.path.join(slot.path, mutant["file"])
    with open(path) as f:
        text = f.read()
    if text.count(mutant["original"]) != 1:
        raise RuntimeError(f"{mutant['name']}: {mutant['file']} in {slot.path} does not hold the text once")
    with open(path, "w") as f:
        f.write(text.replace(mutant["original"], mutant["replacement"]))
    return text


def restore(slot, mutant, text):
    with open(os.path.join(slot.path, mutant["file"]), "w") as f:
        f.write(text)


VERDICT_ORDER = {"build": 3, "named": 0, "unnamed": 1, "missed": 2}


def run_mutant(slot, mutant, baseline_skip, scratch_root):
    started = time.monotonic()
    result = dict(name=mutant["name"], kind=mutant["kind"], file=mutant["file"], board=mutant["board"],
                  images={})
    saved = apply(slot, mutant)
    try:
        for image in mutant["images"]:
            ok, out = slot.build(image)
            if not ok:
                lines = out.splitlines()
                err = [ln for ln in lines if "error:" in ln] or [ln for ln in lines if "error" in ln.lower()]
                result["images"][image] = dict(verdict="build", causes=[], failures=[(err or ["build failed"])[0][:300]])
                continue
            verdict, causes, failures = judge(slot.elf(image), image,
                                              os.path.join(scratch_root, "runs", mutant["name"], image),
                                              baseline_skip[image])
            result["images"][image] = dict(verdict=verdict, causes=causes, failures=failures)
    finally:
        restore(slot, mutant, saved)
    verdicts = [v["verdict"] for v in result["images"].values()]
    # The mutant's verdict: the best any of its images got (a bug the twin names on one part is caught).
    built = [v for v in verdicts if v != "build"]
    result["verdict"] = min(built, key=VERDICT_ORDER.get) if built else "build"
    result["seconds"] = round(time.monotonic() - started, 1)
    return result


def line_for(r):
    first = ""
    for image, v in r["images"].items():
        if v["verdict"] == r["verdict"]:
            first = (v["causes"] or v["failures"] or [""])[0]
            break
    return f"{r['verdict']:8} {r['name']:36} {','.join(i.replace('lp-mspm0', '') for i in r['images']):24} " \
           f"{r['seconds']:6.1f} s  {first[:160]}"


def summary_lines(results):
    n = len(results)
    counts = {k: sum(1 for r in results if r["verdict"] == k) for k in ("named", "unnamed", "missed", "build")}
    built = n - counts["build"]
    pct = (lambda k: 100.0 * k / built) if built else (lambda k: 0.0)
    caught = counts["named"] + counts["unnamed"]
    return [f"mutants {n}: built {built}, compiler-caught {counts['build']}",
            f"twin catch rate {caught}/{built} = {pct(caught):.1f} % (named {counts['named']} = "
            f"{pct(counts['named']):.1f} %, unnamed {counts['unnamed']} = {pct(counts['unnamed']):.1f} %); "
            f"missed {counts['missed']} = {pct(counts['missed']):.1f} %"], counts


def write_markdown(path, results, lines, seconds):
    with open(path, "w") as f:
        f.write("# Mutation run of bsp/mspm0 on the twin (tests/twin/mutants.py)\n\n")
        for ln in lines:
            f.write(f"- {ln}\n")
        f.write(f"- wall time {seconds / 60:.1f} min\n\n| mutant | kind | images | verdict | cause or first failure | "
                "board |\n|---|---|---|---|---|---|\n")
        for r in results:
            cause = ""
            for v in r["images"].values():
                if v["verdict"] == r["verdict"]:
                    cause = (v["causes"] or v["failures"] or [""])[0]
                    break
            cause = cause.replace("|", "/")[:200]
            f.write(f"| {r['name']} | {r['kind']} | {', '.join(r['images'])} | {r['verdict']} | {cause} | "
                    f"{r['board']} |\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--only", default="")
    parser.add_argument("--jobs", type=int, default=1, choices=(1, 2))
    parser.add_argument("--scratch", default=os.path.join(ROOT, "build", "mutants"))
    parser.add_argument("--json", default="")
    parser.add_argument("--markdown", default="")
    args = parser.parse_args()

    problems = validate(MUTANTS, ROOT)
    if problems:
        for p in problems:
            print(f"mutants_table.py: {p}")
        return 1
    mutants = MUTANTS
    if args.only:
        wanted = args.only.split(",")
        unknown = [w for w in wanted if w not in {m["name"] for m in MUTANTS}]
        if unknown:
            print(f"mutants.py: no mutant named {', '.join(unknown)} (--list shows them)")
            return 2
        mutants = [m for m in MUTANTS if m["name"] in wanted]
    if args.list:
        for m in mutants:
            print(f"{m['name']:36} {m['kind']:9} {m['file'][len('bsp/mspm0/'):]:40} {','.join(m['images'])}")
        print(f"{len(mutants)} mutants; every original text occurs exactly once in the current tree")
        return 0
    for tool in (SIM, REGMAPGEN):
        if not os.path.exists(tool):
            print(f"mutants.py: {tool} is not built (cmake --build --preset host --target bms-sim regmapgen)")
            return 1

    started = time.monotonic()
    slots = [Slot(os.path.join(args.scratch, f"slot{i}"), 2 if args.jobs == 1 else 1,
                  None) for i in range(args.jobs)]
    for s in slots:
        s.sync()
    # Baseline: every image the selection uses, unmutated, built in every slot; its failing checks are left out.
    images = sorted({i for m in mutants for i in m["images"]})
    baseline_skip = {}
    for image in images:
        for s in slots:
            ok, out = s.build(image)
            if not ok:
                print(f"mutants.py: the unmutated {image} does not build in {s.path}:\n{out}")
                return 1
        scratch = os.path.join(args.scratch, "runs", "_baseline", image)
        causes, _ = probe(slots[0].elf(image), scratch)
        skip = set()
        for kind, check in checks_for(image):
            ok, why = run_check(kind, check, slots[0].elf(image), scratch)
            if not ok:
                skip.add((kind, check))
                print(f"baseline {image}: {why} (left out for this image)")
        if causes:
            print(f"baseline {image}: the twin reports {causes} on the unmutated image")
        baseline_skip[image] = skip
    print(f"baseline: {len(images)} images built and checked in {time.monotonic() - started:.0f} s")

    queue = list(mutants)
    results = {}
    lock = threading.Lock()

    def worker(slot):
        while True:
            with lock:
                if not queue:
                    return
                mutant = queue.pop(0)
            r = run_mutant(slot, mutant, baseline_skip, args.scratch)
            with lock:
                results[mutant["name"]] = r
                print(line_for(r), flush=True)

    threads = [threading.Thread(target=worker, args=(s,)) for s in slots]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    ordered = [results[m["name"]] for m in mutants]
    seconds = time.monotonic() - started
    lines, counts = summary_lines(ordered)
    for ln in lines:
        print("SUMMARY " + ln)
    print(f"SUMMARY wall time {seconds / 60:.1f} min with --jobs {args.jobs}")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(dict(summary=lines, counts=counts, seconds=round(seconds), jobs=args.jobs,
                           mutants=ordered), f, indent=1)
    if args.markdown:
        write_markdown(args.markdown, ordered, lines, seconds)
    return 0


if __name__ == "__main__":
    sys.exit(main())
