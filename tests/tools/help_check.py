#!/usr/bin/python3
"""--help is complete: every option and operation the parsers accept is in it (bmsctl --help omitted the
BQ769x operations and the bms-sim help most of its options), and everything the help names is accepted.

usage: help_check.py <bms-sim> <bmsctl> <repository>
What the parsers accept is read from their sources: bms-sim's option literals in main.cpp, and per bmsctl
device the operations (`op == "..."`, `operation == "..."`), read/write kinds (`kind == "..."`), options
(checkFlags lists) and --fault kinds of its trace_<family>.cpp. Then each named option or operation is run
and must not be refused as unknown. Prints a REPORT line."""
import os
import re
import subprocess
import sys


def fail(message):
    print("FAIL: " + message)
    sys.exit(1)


def run(*args):
    return subprocess.run(list(args), capture_output=True, text=True, timeout=60)


def check_bms_sim(sim, repo):
    main = open(os.path.join(repo, "bsp/host/tools/bms-sim/main.cpp")).read()
    accepted = set(re.findall(r'"(--[a-z][a-z-]*)"', main)) | {"-h"}
    help_text = run(sim, "--help").stdout
    listed = set(re.findall(r"^  (--[a-z-]+)", help_text, re.M))
    missing = sorted(o for o in accepted if o != "-h" and o not in listed)
    if missing:
        fail(f"bms-sim --help leaves out {missing}")
    if "-h" not in help_text:
        fail("bms-sim --help does not name -h")
    # Everything the help lists is an option the parser knows (a wrong value is fine: not "unknown option").
    for option in sorted(listed):
        r = run(sim, option, "x")
        if f"unknown option '{option}'" in r.stderr:
            fail(f"bms-sim --help lists {option}, the parser refuses it: {r.stderr!r}")
    for image in re.findall(r"^  (lp-mspm0\S+)", help_text, re.M):
        if image not in main and "images()" not in main:
            fail(f"{image} listed without a registry")
    if "exit status" not in help_text:
        fail("bms-sim --help does not give the exit statuses")
    return len(listed)


def device_sections(help_text):
    """Device name -> its block of the bmsctl help (the device line and the indented lines under it)."""
    out, current = {}, None
    for line in help_text.splitlines():
        m = re.match(r"^  (\S+)\s", line)
        if m and not line.startswith("    "):
            current = m.group(1)
            out[current] = line + "\n"
        elif current and line.startswith("    "):
            out[current] += line + "\n"
    return out


def check_bmsctl(ctl, repo):
    help_text = run(ctl, "--help").stdout
    sections = device_sections(help_text)
    folder = os.path.join(repo, "bsp/host/tools/bmsctl")
    checked = 0
    for name in sorted(os.listdir(folder)):
        if not name.startswith("trace_") or not name.endswith(".cpp"):
            continue
        src = open(os.path.join(folder, name)).read()
        devices = re.findall(r'Registrar \w+\{\s*\{"([a-z0-9]+)"', src)
        ops = set(re.findall(r'\b(?:op|operation) [!=]= "([a-z-]+)"', src))
        kinds = set(re.findall(r'\bkind == "([a-z]+)"', src))
        flags = set(re.findall(r'"(--[a-z]+)"', src))
        faults = set()
        m = re.search(r"known\[\] = \{([^}]*)\}", src)
        if m:
            faults = set(re.findall(r'"([a-z-]+)"', m.group(1)))
        if not devices or not ops:
            fail(f"{name}: no registered device or no operation found (the parser changed shape?)")
        for device in devices:
            text = sections.get(device)
            if text is None:
                fail(f"bmsctl --help has no section for {device}")
            for word in sorted(ops | kinds | flags | faults):
                if not re.search(r"(?<![\w-])" + re.escape(word) + r"(?![\w-])", text):
                    fail(f"bmsctl --help, {device}: '{word}' ({name} accepts it) is not in\n{text}")
                checked += 1
            for op in sorted(ops):
                r = run(ctl, "trace", device, op)
                if "unknown" in r.stderr and "operation" in r.stderr:
                    fail(f"bmsctl trace {device} {op}: {r.stderr!r}")
    return checked


def main():
    if len(sys.argv) != 4:
        print(__doc__)
        return 2
    sim, ctl, repo = sys.argv[1:]
    options = check_bms_sim(sim, repo)
    words = check_bmsctl(ctl, repo)
    print(f"REPORT help: bms-sim --help names its {options} options; bmsctl --help names {words} operations, "
          "kinds and options of its devices")
    print("ok")
    return 0


if __name__ == "__main__":
    sys.exit(main())
