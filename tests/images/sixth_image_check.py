#!/usr/bin/python3
"""Adding an image is adding a folder (bsp/mspm0/README.md "Adding an image"): this check copies the source tree,
adds tests/images/sixth/lp-mspm0g3507-bq76907 as bsp/mspm0/images/lp-mspm0g3507-bq76907 and its two presets to
CMakePresets.json (the one other place), changes nothing else, and shows that
  - the image builds within its chip's budget and names itself in its ELF (.bms_image);
  - the host configuration picks it up everywhere the five are: bms-sim's generated image list, its own
    simulator, the latency and path tests, the twin checks, `bmsctl flash` and the imbalance runs;
  - ./ci/test would build and test it (its listing of the image folders);
  - the image itself runs on the twin (bms-sim --elf, the copy's ELF): it publishes, and trips cell
    over-voltage.

usage: sixth_image_check.py <source-dir> <scratch-dir> <bms-sim>"""
import json
import os
import shutil
import subprocess
import sys

IMAGE = "lp-mspm0g3507-bq76907"
source, scratch, bms_sim = sys.argv[1:4]
here = os.path.dirname(os.path.abspath(__file__))


def fail(message):
    print(f"FAIL: {message}")
    sys.exit(1)


def run(*args, cwd=None):
    r = subprocess.run(args, cwd=cwd, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"{' '.join(args)}: exit {r.returncode}\n{r.stdout[-3000:]}\n{r.stderr[-3000:]}")
    return r.stdout


# The tree as committed (git ls-files), or without build outputs where git is not there.
copy = os.path.join(scratch, "tree")
shutil.rmtree(copy, ignore_errors=True)
try:
    files = subprocess.run(["git", "-C", source, "ls-files", "-z"], capture_output=True, check=True).stdout
    names = [n for n in files.decode().split("\0") if n]
except (OSError, subprocess.CalledProcessError):
    names = [os.path.relpath(os.path.join(d, f), source) for d, ds, fs in os.walk(source) for f in fs
             if "/build" not in d and "/.git" not in d]
for name in names:
    src = os.path.join(source, name)
    if not os.path.isfile(src):
        continue
    os.makedirs(os.path.dirname(os.path.join(copy, name)), exist_ok=True)
    shutil.copy2(src, os.path.join(copy, name))

# The folder, and the presets.
shutil.copytree(os.path.join(here, "sixth", IMAGE), os.path.join(copy, "bsp", "mspm0", "images", IMAGE))
presets_path = os.path.join(copy, "CMakePresets.json")
with open(presets_path) as f:
    presets = json.load(f)
presets["configurePresets"].append({"name": IMAGE, "inherits": "cross",
                                    "displayName": "LP-MSPM0G3507 + BQ76907 over I2C, CAN out",
                                    "cacheVariables": {"BMS_TARGET": "mspm0", "BMS_IMAGE": IMAGE}})
presets["buildPresets"].append({"name": IMAGE, "configurePreset": IMAGE})
with open(presets_path, "w") as f:
    json.dump(presets, f, indent=2)

# ./ci/test's image list is the folders.
listed = subprocess.run(["bash", "-c", "for d in bsp/mspm0/images/*/image.cmake; do basename $(dirname $d); done"],
                        cwd=copy, capture_output=True, text=True).stdout.split()
if IMAGE not in listed:
    fail(f"ci/test's listing of bsp/mspm0/images/*/image.cmake misses {IMAGE}: {listed}")
with open(os.path.join(copy, "ci", "test")) as f:
    if "bsp/mspm0/images/*/image.cmake" not in f.read():
        fail("ci/test no longer lists the image folders")

# The image: configured and built from its preset alone.
run("cmake", "--preset", IMAGE, cwd=copy)
out = run("cmake", "--build", "--preset", IMAGE, cwd=copy)
size = [line for line in out.splitlines() if line.startswith(f"size {IMAGE}:")]
if not size:
    fail(f"no size line for {IMAGE} in the build output:\n{out[-2000:]}")
elf = os.path.join(copy, "build", IMAGE, IMAGE + ".elf")
name_file = os.path.join(scratch, "bms_image.bin")
run("arm-none-eabi-objcopy", "-O", "binary", "--only-section=.bms_image", "--set-section-flags", ".bms_image=alloc",
    elf, name_file)
with open(name_file, "rb") as f:
    named = f.read().split(b"\0")[0].decode().strip()
if named != IMAGE:
    fail(f"the ELF names itself {named!r}, not {IMAGE}")
print(f"REPORT sixth image: {size[0]}")

# The host configuration: every per-image test and tool the five have.
run("cmake", "--preset", "host", cwd=copy)
generated = open(os.path.join(copy, "build", "host", "bsp", "host", "tools", "bms-sim", "generated",
                              "image_descriptions.hpp")).read()
if f'"{IMAGE}", "bq769x2", "g3507_can", "bq76907"' not in generated:
    fail(f"bms-sim's generated image list misses {IMAGE}")
tests = run("ctest", "--test-dir", os.path.join(copy, "build", "host"), "-N")
for expected in (f"twin.ov-cell.{IMAGE}", f"twin.imbalance.{IMAGE}", f"twin.soc-count.{IMAGE}",
                 f"bms_sim.imbalance.{IMAGE}", f"bms_sim.ov_cell.{IMAGE}", f"bms_sim.commands_send.{IMAGE}",
                 f"bmsctl.flash.flash-{IMAGE}", f"twin.commands_send.{IMAGE}"):
    if expected not in tests:
        fail(f"the host configuration has no test {expected}")
targets = run("cmake", "--build", os.path.join(copy, "build", "host"), "--target", "help")
for expected in (f"bms-sim-{IMAGE}", f"latency_sweep_tests_{IMAGE}", f"path_truth_tests_{IMAGE}"):
    if expected not in targets:
        fail(f"the host configuration has no target {expected}")

# The image on the twin: it publishes and trips cell over-voltage (the twin knows it by its ELF's name).
summary = json.loads(run(bms_sim, "--elf", elf, "--scenario", "ov-cell", "--duration", "3000", "--json"))
events = [e["fault"] for e in summary.get("protection_events", [])]
if summary.get("can_frames", 0) == 0 or "cell_ov" not in events:
    fail(f"the sixth image on the twin: {summary.get('can_frames')} frames, protection events {events}")
print(f"REPORT sixth image on the twin: {summary['can_frames']} CAN frames in 3 s, protection events {events}")
shutil.rmtree(copy, ignore_errors=True)
