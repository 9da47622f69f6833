#!/usr/bin/python3
"""`bmsctl flash` end to end against the twin's ROM bootloader (issue 25): twin-bsl puts a LaunchPad set-up on
a pseudo-terminal, bmsctl flashes an image through it, and the twin then runs what was flashed. Every failure
is checked for its exact message and exit status (bsp/host/tools/bmsctl/flash/flash_command.hpp).

usage: bmsctl_flash.py <check> <bmsctl> <twin-bsl> <images-dir> <scratch-dir>
checks:
  flash-<preset>  a blank twin of that board flashed from the image's .elf, .hex or .bin; the twin then runs
                  it, and it publishes the same frames at the same times as the image loaded directly
  report          REPORT: a G3507 image flashed at 115 200 Bd, in simulated time, against the wire minimum
  wrong-password  a part with another password: exit 9 and never a second Unlock per run; the third wrong
                  password of the session ends in exit 10 (security alert); the right one (--password FILE) flashes
  no-answer       a port nothing answers on: exit 8 with the LaunchPad's invoke procedure
  reply-crc       a core answer with a bad CRC (device info: asked again; Program Data: erased and programmed
                  again): exit 0 with the warnings, and the image runs
  dropped-byte    a byte of a Program Data packet lost on the line: resynchronised, sent again, exit 0
  cut             the power goes after the first Program Data: exit 12; the device comes back in its BSL by
                  itself (reset vector still erased) and a second run flashes it
  nonmain, sram   an image with a byte in NONMAIN / SRAM: exit 4 before the port is touched
  other-chip      an L1306 image into a G3507: exit 5 (from the device's answer, and from --chip)
  missing-port    exit 6;  busy-port: a port another program holds, exit 7
  crc-mismatch    a flash bit flipped after programming: exit 11 naming the window and both CRCs
  verify-only     --verify-only against the flashed image (exit 0) and another one (exit 11)
  invoke-button   --invoke button prints the LaunchPad's procedure and flashes once the BSL answers
  password-file   a malformed password file: exit 2 at file:line:col
  flash-target    `cmake --build <images-dir>/<preset> --target flash` with BMS_FLASH_PORT naming the twin's port
                  (cmake from the environment variable CMAKE, else PATH)
  invoke-app-host --invoke app's frames against a stand-in for the image on a pseudo-terminal (bms.yaml's
                  Identify / IdentifyVersion / IdentifyChip / EnterBootloader / CommandAck, CRC-8 SAE J1850
                  computed here): accepted (then the BSL is looked for), refused, another part's image, silence.
  invoke-app-<preset>  end to end: twin-bsl runs the image with its command link on a second pseudo-terminal
                  (--command-pty: the L1306's back-channel UART, an SLCAN adapter on the G3507's CAN bus);
                  `bmsctl flash --invoke app --invoke-port` sends Identify and EnterBootloader there; the image
                  turns its paths off (FETs, fault output), answers, and restarts into the BSL (RESETLEVEL BOOTLOADERENTRY), which
                  takes the image; the flashed image then publishes as one loaded directly.
Exit 77 (skipped) when an image is not built."""
import fcntl
import os
import pty
import re
import select
import subprocess
import sys
import threading
import time

# How each image is flashed in its check: the three file formats and the line rates between them (an image
# not named here, e.g. one just added as a folder, goes as its ELF at 115 200 Bd).
HOW = {
    "lp-mspm0l1306-bq76952": (".hex", 9600),
    "lp-mspm0l1306-bq76907": (".elf", 115200),
    "lp-mspm0g3507-bq79616": (".elf", 115200),
    "lp-mspm0g3507-bq4050": (".bin", 115200),
    "lp-mspm0g3507-bq76952": (".elf", 1000000),
}
RUN_MS = 1500

bmsctl, twin_bsl, images, scratch = sys.argv[2:6]
os.makedirs(scratch, exist_ok=True)
failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what)


def image(preset, ext=".elf"):
    path = os.path.join(images, preset, preset + ext)
    if not os.path.exists(path):
        print(f"SKIP: {path} is not built (./ci/test builds it)")
        sys.exit(77)
    return path


class Twin:
    """twin-bsl running in the background; path is its BSL UART."""

    def __init__(self, board, *args, frames=None):
        cmd = [twin_bsl, "--board", board, "--run", str(RUN_MS), "--timeout", "90", *args]
        if frames:
            cmd += ["--frames", frames]
        self.proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.lines = []
        while True:
            line = self.proc.stdout.readline()
            if not line:
                raise RuntimeError("twin-bsl ended before its BSL UART was up: " + "".join(self.lines))
            self.lines.append(line)
            m = re.search(r"BSL UART on (\S+)", line)
            if m:
                self.path = m.group(1)
                if "--command-pty" not in args:
                    break
            m = re.search(r"command link on (\S+)", line)
            if m:
                self.command_path = m.group(1)
                break

    def finish(self, timeout=120):
        out, _ = self.proc.communicate(timeout=timeout)
        self.lines += out.splitlines(True)
        return self.proc.returncode, "".join(self.lines)

    def kill(self):
        self.proc.kill()
        out, _ = self.proc.communicate()
        self.lines += out.splitlines(True)
        return "".join(self.lines)


def flash(path, port, *args):
    r = subprocess.run([bmsctl, "flash", path, "--port", port, *args], capture_output=True, text=True, timeout=120)
    return r.returncode, r.stdout, r.stderr


def frames(path):
    with open(path) as f:
        return [line.split() for line in f if line.strip()]


def direct(preset):
    """The image loaded into the twin's flash directly: the frames it publishes."""
    out = os.path.join(scratch, preset + ".direct.frames")
    r = subprocess.run([twin_bsl, "--board", preset, "--elf", image(preset), "--run", str(RUN_MS), "--frames", out],
                       capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, f"direct run of {preset}: exit {r.returncode}: {r.stdout}")
    return frames(out)


def same_frames(preset, flashed_path, reset_cause=None):
    got, want = frames(flashed_path), direct(preset)
    if reset_cause is not None:
        # The Startup message (0x1F0) gives the reset cause in its first byte: after the image's own
        # software invoke it read RSTCAUSE already, so the BSL's exit reset is the lowest-level cause left.
        startup = [f for f in got if f[1] == "1f0"]
        check(len(startup) == 1 and startup[0][2][:2] == "%02X" % reset_cause,
              f"{preset}: Startup after the BSL gives reset cause 0x{reset_cause:02X}: {startup}")
        for f in startup:
            f[2] = "01" + f[2][2:]  # else as after the power-on of the direct run
        # The monitor kept its state through the MCU's reset (a BQ79616 chain stays awake, a BQ76952 stays
        # configured): until the first PackSummary with a pack voltage in both runs, one run's values may
        # still be "not available" where the other has readings.
        def first_valid(frames):
            return next((i for i, f in enumerate(frames) if f[1] == "100" and not f[2].startswith("FFFF")), 0)

        for i in range(min(max(first_valid(got), first_valid(want)), len(want), len(got))):
            if got[i][1] == want[i][1]:
                got[i][2] = want[i][2]
        # An image that keeps its state of charge (the record store: firmware/app/store) writes it before
        # the commanded reset into the BSL and restores it after: the same value, with the basis `restored`
        # (StateOfCharge 0x104 byte 7, low nibble 4) where the direct run's first value came from the
        # open-circuit table. Everything else of the frame must match.
        for g, w in zip(got, want):
            if g[1] == w[1] == "104" and g[2][14:16] == "04" and g[2][:14] == w[2][:14]:
                g[2] = w[2]
    # StorageStatus (0x105) carries the measurement's age in ms at the instant it goes out: the frame times may
    # differ by up to 1 ms (below), and so may the age. Everything else of the frame must match.
    for g, w in zip(got, want):
        if g[1] == w[1] == "105" and len(g[2]) == len(w[2]) == 16 and g[2][:6] == w[2][:6] and \
                g[2][12:] == w[2][12:] and abs(int(g[2][10:12] + g[2][8:10] + g[2][6:8], 16) -
                                                int(w[2][10:12] + w[2][8:10] + w[2][6:8], 16)) <= 1:
            g[2] = w[2]
    check(len(want) > 0, f"{preset}: the image published no frames in {RUN_MS} ms")
    check([f[1:] for f in got] == [f[1:] for f in want],
          f"{preset}: flashed image publishes other frames than the image loaded directly "
          f"({len(got)} against {len(want)})")
    worst = max((abs(int(a[0]) - int(b[0])) for a, b in zip(got, want)), default=0)
    check(worst <= 1000, f"{preset}: frame times differ by up to {worst} us")
    return len(got), worst


def flash_and_run(preset, ext, baud, *twin_args, bmsctl_args=(), expect_exit=0):
    out = os.path.join(scratch, preset + ".flashed.frames")
    if os.path.exists(out):
        os.remove(out)
    twin = Twin(preset, *twin_args, frames=out)
    code, stdout, stderr = flash(image(preset, ext), twin.path, "--baud", str(baud), *bmsctl_args)
    check(code == expect_exit, f"bmsctl flash {preset}{ext} at {baud} Bd: exit {code} (want {expect_exit})\n{stderr}")
    if code != 0:
        twin.kill()
        return twin, stdout, stderr, None
    rc, log = twin.finish()
    check(rc == 0, f"twin-bsl after flashing {preset}: exit {rc}\n{log}")
    return twin, stdout, stderr, log


def c_flash(preset):
    ext, baud = HOW.get(preset, (".elf", 115200))
    twin, stdout, stderr, log = flash_and_run(preset, ext, baud)
    check(re.match(r"bmsctl: flashed \S+ \((ELF|Intel HEX|binary), \d+ B\) into the MSPM0(L1306|G3507) at %d Bd in "
                   r"[\d.]+ s: \d+ sectors erased, \d+ B in \d+ packets, CRC verified, application started\n$" % baud,
                   stdout), f"summary line: {stdout!r}")
    check(stderr == "", f"nothing on stderr when all goes well: {stderr!r}")
    if log is None:
        return
    check("BSL started: MAIN flash blank" in log, "the blank twin started in its BSL")
    check("application started" in log, "the twin started the flashed application")
    n, worst = same_frames(preset, os.path.join(scratch, preset + ".flashed.frames"))
    print(f"REPORT bmsctl flash {preset}{ext} at {baud} Bd: then {n} frames in {RUN_MS} ms, the same as the image "
          f"loaded directly (worst time difference {worst} us)")


def c_keeps_data():
    """The flash data region (0x7000..0x7FFF, bsp/mspm0/linker) holds records from before: a reflash over the
    BSL erases only the image's sectors (Flash Range Erase), so every byte of the region survives it."""
    preset = "lp-mspm0l1306-bq76907"
    ext, baud = HOW.get(preset, (".elf", 115200))
    data = os.path.join(scratch, "data-region.bin")
    before = bytes((i * 7 + 3) & 0xFF for i in range(4096))
    with open(data, "wb") as f:
        f.write(before)
    twin, stdout, stderr, log = flash_and_run(preset, ext, baud, "--flash", data)
    check(log is not None and "application started" in log, "the flashed application ran")
    with open(data, "rb") as f:
        after = f.read()
    changed = sum(1 for a, b in zip(before, after) if a != b) + abs(len(after) - len(before))
    check(changed == 0, f"the data region survives the reflash: {changed} of 4096 bytes changed")
    print(f"REPORT bmsctl flash {preset}{ext}: {4096 - changed} of 4096 bytes of the data region kept")


def c_report():
    preset = "lp-mspm0g3507-bq79616"
    twin, stdout, stderr, log = flash_and_run(preset, ".elf", 115200)
    m = re.search(r"BSL session ([\d.]+) s simulated", log or "")
    check(m is not None, "twin-bsl reports the session time")
    size = int(re.search(r"\((?:ELF), (\d+) B\)", stdout).group(1))
    wire = size * 10 / 115200
    if m:
        print(f"REPORT bmsctl flash {preset} ({size} B) at 115200 Bd over the twin: {float(m.group(1)):.2f} s of "
              f"simulated time from Connection to Start Application (wire minimum for the image {wire:.2f} s; "
              f"the host's turnaround between packets counts at wall-clock pace)")


def c_wrong_password():
    preset = "lp-mspm0g3507-bq76952"
    twin = Twin(preset, "--password", "00" * 32, "--log")
    want = ("bmsctl: error: wrong BSL password (MSG 0x02 (BSL password error)); not retried: each wrong password costs "
            "a 2 s lockout and the third one the device's security alert (SLAU887 4.3.3). Give the 32-byte password "
            "with --password FILE\n")
    already = "bmsctl: warning: the BSL's session was open already (MSG 0x06 to Connection): continuing in it\n"
    code, _, stderr = flash(image(preset), twin.path)
    check(code == 9 and stderr == want, f"wrong password, run 1: exit {code}, {stderr!r}")
    # The next run waits out the 2 s penalty and finds the session open.
    code, _, stderr = flash(image(preset), twin.path)
    check(code == 9 and stderr == already + want, f"wrong password, run 2: exit {code}, {stderr!r}")
    code, _, stderr = flash(image(preset), twin.path)
    check(code == 10 and stderr == already +
          "bmsctl: error: MSG 0x03 (third wrong password, the security alert was taken): the device took its "
          "configured security alert; reset it and give the right --password\n",
          f"third wrong password: exit {code}, {stderr!r}")
    password = os.path.join(scratch, "password.txt")
    with open(password, "w") as f:
        f.write("0x00, " * 32 + "\n")
    code, stdout, stderr = flash(image(preset), twin.path, "--password", password)
    check(code == 0 and stderr == already, f"the right password: exit {code}, {stderr!r}")
    rc, log = twin.finish()
    unlocks = log.count("BSL Unlock:")
    check(unlocks == 4, f"one Unlock per run, four runs: the twin saw {unlocks}")


def c_no_answer():
    master, slave = pty.openpty()
    path = os.ttyname(slave)
    start = time.monotonic()
    code, _, stderr = flash(image("lp-mspm0g3507-bq79616"), path, "--wait", "2")
    took = time.monotonic() - start
    check(code == 8, f"no answer: exit {code}")
    check(stderr.startswith(f"bmsctl: error: no answer from the bootloader on {path} within 2 s. Start it on the "
                            "LP-MSPM0G3507: hold S1 (PA18), press and release the reset button NRST, release S1 at "
                            "least 100 ms later; the BSL then listens for 10 s on PA11 (RX) / PA10 (TX)"),
          f"no-answer message: {stderr!r}")
    check(1.9 < took < 10, f"bmsctl waited {took:.1f} s for --wait 2")
    sent = os.read(master, 4096)
    check(sent[:8] == bytes.fromhex("80010012 3A6144DE"), "it sent SLAU887's Connection packet")
    os.close(master)
    os.close(slave)


def c_reply_crc():
    preset = "lp-mspm0g3507-bq79616"
    # The first Program Data answer (device info 1, unlock 2, erase 3, program 4) arrives with a bad CRC.
    _, _, stderr, log = flash_and_run(preset, ".elf", 115200, "--corrupt-answer", "4")
    check(stderr == "bmsctl: warning: a reply that failed its CRC check to Program Data at 0x00000008\n"
                    "bmsctl: warning: cannot tell whether Program Data at 0x00000008 was written; erasing and "
                    "programming again (pass 2 of 2)\n", f"warnings: {stderr!r}")
    if log:
        same_frames(preset, os.path.join(scratch, preset + ".flashed.frames"))
    _, _, stderr, log = flash_and_run(preset, ".elf", 9600, "--corrupt-answer", "1")
    check(stderr == "bmsctl: warning: a reply that failed its CRC check to Get Device Info; resynchronised and sent it "
                    "again (attempt 2 of 3)\n", f"warnings: {stderr!r}")


def c_dropped_byte():
    preset = "lp-mspm0g3507-bq4050"
    # Connection 8, device info 8, baud 9, unlock 39, erase 16 bytes: byte 100 is in the first Program Data.
    _, _, stderr, log = flash_and_run(preset, ".elf", 115200, "--drop-host-byte", "100")
    check(stderr == "bmsctl: warning: no acknowledgement for Program Data at 0x00000008; resynchronised and sent it "
                    "again (attempt 2 of 3)\n", f"warnings: {stderr!r}")
    if log:
        same_frames(preset, os.path.join(scratch, preset + ".flashed.frames"))


def c_cut():
    preset = "lp-mspm0g3507-bq76952"
    out = os.path.join(scratch, preset + ".flashed.frames")
    twin = Twin(preset, "--power-loss-after", "1", frames=out)
    code, _, stderr = flash(image(preset), twin.path, "--baud", "115200")
    check(code == 12, f"cut download: exit {code}")
    resend = "bmsctl: warning: no acknowledgement for Program Data at 0x00001008; resynchronised and sent it again "
    check(re.fullmatch(re.escape(resend + "(attempt 2 of 3)\n" + resend + "(attempt 3 of 3)\n") +
                       r"bmsctl: error: the BSL stopped answering at Program Data at 0x00001008 \(4096 of \d+ B "
                       r"written, 3 attempts\); the reset vector is written last, so the device starts its bootloader "
                       r"again at its next reset: run bmsctl again\n", stderr), f"cut message: {stderr!r}")
    code, stdout, stderr = flash(image(preset), twin.path, "--baud", "115200")
    check(code == 0, f"second run after the cut: exit {code}\n{stderr}")
    rc, log = twin.finish()
    check(rc == 0, f"twin-bsl: exit {rc}")
    lost = log.find("power lost")
    check(lost >= 0 and log.find("BSL started: MAIN flash blank", lost) > lost,
          f"after the power came back the blank reset vector started the BSL again:\n{log}")
    same_frames(preset, out)


def hex_with(extra_records):
    """The G3507 image's .hex with records added before its end-of-file record."""
    src = image("lp-mspm0g3507-bq79616", ".hex")
    lines = open(src).read().splitlines()
    path = os.path.join(scratch, "extra.hex")
    with open(path, "w") as f:
        f.write("\n".join(lines[:-1] + extra_records + lines[-1:]) + "\n")
    return path


def record(count, address, kind, data):
    b = [count, address >> 8, address & 0xFF, kind] + data
    return ":" + "".join("%02X" % x for x in b) + "%02X" % ((-sum(b)) & 0xFF)


def c_outside(upper, where):
    path = hex_with([record(2, 0, 4, [upper >> 8, upper & 0xFF]), record(4, 0, 0, [1, 2, 3, 4])])
    code, _, stderr = flash(path, "/dev/nonexistent-bsl-port")
    base = upper << 16
    check(code == 4, f"{where}: exit {code} (refused before the port: not 6)")
    check(stderr == f"bmsctl: error: {path}: 4 bytes at 0x{base:08X}..0x{base + 3:08X} lie in {where}, outside MAIN "
                    "flash of the MSPM0G3507 (0x00000000..0x0001FFFF); bmsctl writes MAIN flash only\n",
          f"{where} message: {stderr!r}")


def c_other_chip():
    l1306 = image("lp-mspm0l1306-bq76952")
    twin = Twin("lp-mspm0g3507-bq79616")
    code, _, stderr = flash(l1306, twin.path)
    check(code == 5 and stderr == f"bmsctl: error: the device is an MSPM0G3507 (BSL buffer 0x3EC0); {l1306} is for "
                                  "the MSPM0L1306\n", f"other chip: exit {code}, {stderr!r}")
    twin.kill()
    code, _, stderr = flash(l1306, "/dev/nonexistent-bsl-port", "--chip", "mspm0g3507")
    check(code == 5 and stderr == f"bmsctl: error: {l1306} is an MSPM0L1306 image (initial stack pointer 0x20001000), "
                                  "not for the MSPM0G3507 --chip names\n", f"--chip: exit {code}, {stderr!r}")


def c_missing_port():
    code, _, stderr = flash(image("lp-mspm0g3507-bq79616"), "/dev/nonexistent-bsl-port")
    check(code == 6 and stderr.startswith("bmsctl: error: /dev/nonexistent-bsl-port: no such port (No such file or "
                                          "directory)"), f"missing port: exit {code}, {stderr!r}")


def c_busy_port():
    twin = Twin("lp-mspm0g3507-bq79616")
    holder = os.open(twin.path, os.O_RDWR | os.O_NOCTTY)
    fcntl.flock(holder, fcntl.LOCK_EX)
    code, _, stderr = flash(image("lp-mspm0g3507-bq79616"), twin.path)
    check(code == 7 and stderr.startswith(f"bmsctl: error: {twin.path} is in use by another program (another program "
                                          "holds its lock)"), f"busy port: exit {code}, {stderr!r}")
    os.close(holder)
    code, _, stderr = flash(image("lp-mspm0g3507-bq79616"), twin.path)
    check(code == 0, f"once released: exit {code} {stderr}")
    twin.finish()


def c_crc_mismatch():
    preset = "lp-mspm0g3507-bq79616"
    _, _, stderr, _ = flash_and_run(preset, ".elf", 115200, "--flip-bit", "0x100", expect_exit=11)
    # The window is the image's sectors from 0 (its end moves with the image's size: 1 KiB sectors).
    check(re.fullmatch(r"bmsctl: error: CRC mismatch in 0x00000000\.\.0x0000[0-9A-F]{2}FF: the device reports 0x[0-9A-F]{8}, "
                       r"the image gives 0x[0-9A-F]{8} \(flash again\)\n", stderr), f"mismatch message: {stderr!r}")


def c_verify_only():
    preset = "lp-mspm0g3507-bq79616"
    twin = Twin(preset, "--elf", image(preset), "--s1")
    code, stdout, stderr = flash(image(preset), twin.path, "--verify-only")
    check(code == 0 and re.match(r"bmsctl: \S+ matches the MSPM0G3507's flash: 1 window, \d+ B, CRC verified\n$",
                                 stdout), f"verify-only, same image: exit {code} {stdout!r} {stderr!r}")
    code, _, stderr = flash(image("lp-mspm0g3507-bq4050"), twin.path, "--verify-only")
    check(code == 11 and "(the flash holds something else)" in stderr, f"verify-only, other image: exit {code} {stderr!r}")
    twin.kill()


def c_invoke_button():
    preset = "lp-mspm0g3507-bq4050"
    out = os.path.join(scratch, preset + ".flashed.frames")
    twin = Twin(preset, "--elf", image("lp-mspm0g3507-bq79616"), "--s1", frames=out)
    code, stdout, stderr = flash(image(preset), twin.path, "--invoke", "button")
    check(code == 0, f"--invoke button: exit {code} {stderr}")
    check(stderr.startswith("bmsctl: start the bootloader on the LP-MSPM0G3507: hold S1 (PA18), press and release "
                            "the reset button NRST"), f"procedure printed: {stderr!r}")
    rc, log = twin.finish()
    check("BSL started: invoke pin PA18 high at reset" in log, "the twin's BSL was started by S1")
    same_frames(preset, out)


def c_password_file():
    path = os.path.join(scratch, "bad-password.txt")
    with open(path, "w") as f:
        f.write("FF" * 16 + "\n" + "FF" * 5 + "GG\n")
    code, _, stderr = flash(image("lp-mspm0g3507-bq79616"), "/dev/nonexistent-bsl-port", "--password", path)
    check(code == 2 and stderr == f"bmsctl: error: {path}:2:11: not a hex digit\n", f"password file: {code} {stderr!r}")


def c_flash_target():
    preset = "lp-mspm0l1306-bq76907"
    image(preset)
    out = os.path.join(scratch, preset + ".flashed.frames")
    build = [os.environ.get("CMAKE", "cmake"), "--build", os.path.join(images, preset)]
    # The image first (the target depends on it): a blank part's BSL waits only 10 s for its Connection.
    r = subprocess.run(build, capture_output=True, text=True, timeout=600)
    check(r.returncode == 0, f"building {preset}: exit {r.returncode}\n{r.stdout}\n{r.stderr}")
    twin = Twin(preset, frames=out)
    env = dict(os.environ, BMS_FLASH_PORT=twin.path)
    r = subprocess.run(build + ["--target", "flash"], capture_output=True, text=True, timeout=300, env=env)
    check(r.returncode == 0, f"--target flash: exit {r.returncode}\n{r.stdout}\n{r.stderr}")
    check(f"--port {twin.path} --chip mspm0l1306 --baud 115200 --invoke button" in r.stdout,
          f"the target runs bmsctl flash with the port: {r.stdout}")
    check("bmsctl: start the bootloader on the LP-MSPM0L1306: hold S1 (PA18)" in r.stderr + r.stdout,
          "the button procedure is printed")
    rc, log = twin.finish()
    check(rc == 0, f"twin-bsl: exit {rc}\n{log}")
    same_frames(preset, out)


def crc8_j1850(data):
    crc = 0xFF
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc ^ 0xFF


def fake_image(master, image_number, result, seen, stop):
    """Answers Identify and EnterBootloader on SLCAN lines as bms.yaml lays them out (node 1, TraceId
    0xCAFEF00D); `result` is EnterBootloader's CommandAck result, None for silence."""
    pending = b""

    def send(can_id, data):
        line = "t%03X%d%s\r" % (can_id, len(data), bytes(data).hex().upper())
        os.write(master, line.encode())

    while not stop.is_set():
        if not select.select([master], [], [], 0.05)[0]:
            continue
        pending += os.read(master, 256)
        while b"\r" in pending:
            line, pending = pending.split(b"\r", 1)
            text = line.decode(errors="replace")
            if not re.fullmatch(r"t[0-9A-F]{4}([0-9A-F]{2})*", text):
                continue
            can_id, data = int(text[1:4], 16), bytes.fromhex(text[5:])
            crc_ok = data and data[0] == crc8_j1850(bytes([can_id & 0xFF, can_id >> 8]) + data[1:])
            seen.append((can_id, data, crc_ok))
            if result is None or not crc_ok or data[2] != 1:
                continue
            counter = data[1] & 0xF
            if can_id == 0x603:
                send(0x580, [1, 0x03, 0x06, counter, 0, 0, 0])
                send(0x581, [1, 0, 1, 0, 0, 0, 0, image_number])
                send(0x582, [1, 0x0C, 0x0D, 0xF0, 0xFE, 0xCA, 0x07, 0x35])
            elif can_id == 0x606:
                send(0x580, [1, 0x06, 0x06, counter, result, 0, 0])


def c_invoke_app_host():
    g3507 = image("lp-mspm0g3507-bq79616")
    for image_number, result, want_exit, want in [
            (3, 0, 8, "bmsctl: error: no answer from the bootloader on"),
            (3, 8, 14, "bmsctl: error: node 1 refused EnterBootloader: paths_not_off\n"),
            (1, 0, 5, "bmsctl: error: node 1 runs image 1 (bms.yaml IdentifyVersion.Image), built for the other part "
                      "than the file\n"),
            (3, None, 14, "bmsctl: error: no IdentifyChip answer from node 1 on ")]:
        master, slave = pty.openpty()
        path = os.ttyname(slave)
        seen, stop = [], threading.Event()
        worker = threading.Thread(target=fake_image, args=(master, image_number, result, seen, stop))
        worker.start()
        code, _, stderr = flash(g3507, path, "--invoke", "app", "--wait", "1")
        stop.set()
        worker.join()
        os.close(master)
        os.close(slave)
        check(code == want_exit and stderr.startswith(want),
              f"--invoke app (image {image_number}, result {result}): exit {code}, {stderr!r}")
        check(len(seen) >= 1 and seen[0][0] == 0x603 and seen[0][2] and len(seen[0][1]) == 3,
              f"Identify sent first, with a good CRC: {seen}")
        enter = [f for f in seen if f[0] == 0x606]
        if result is not None and image_number == 3:
            check(len(enter) == 1 and enter[0][2] and enter[0][1][2:] == bytes([1, 0x0D, 0xF0, 0xFE, 0xCA, 0xA5])
                  and enter[0][1][1] & 0xF == (seen[0][1][1] + 1) & 0xF,
                  f"EnterBootloader: node 1, IdentifyChip's TraceId, key 0xA5, the next counter: {enter}")
        else:
            check(not enter, f"no EnterBootloader without a matching image: {enter}")


def c_invoke_app(preset):
    """The image itself takes EnterBootloader, turns its paths off, answers and restarts into the BSL."""
    out = os.path.join(scratch, preset + ".flashed.frames")
    if os.path.exists(out):
        os.remove(out)
    twin = Twin(preset, "--elf", image(preset), "--command-pty", frames=out)
    time.sleep(1.0)  # the image up and publishing (the twin keeps wall-clock pace until the command)
    # On a loaded machine the twin may fall behind wall-clock time while the image boots, and bmsctl waits
    # 1 s for the Identify answer (a board answers within one scan): ask again, as a user would, at most
    # twice more. Any other failure, or a third silence, fails.
    for attempt in range(3):
        start = time.monotonic()
        code, stdout, stderr = flash(image(preset, ".hex"), twin.path, "--baud", "115200", "--invoke", "app",
                                     "--invoke-port", twin.command_path)
        took = time.monotonic() - start
        if code != 14 or "no IdentifyChip answer" not in stderr:
            break
        print(f"attempt {attempt + 1}: no Identify answer within 1 s, asking again")
    check(code == 0, f"bmsctl flash --invoke app {preset}: exit {code}\n{stderr}")
    if code != 0:
        print(twin.kill())
        return
    check(re.match(r"bmsctl: flashed \S+ \(Intel HEX, \d+ B\) into the MSPM0(L1306|G3507) at 115200 Bd in [\d.]+ s: "
                   r"\d+ sectors erased, \d+ B in \d+ packets, CRC verified, application started\n$", stdout),
          f"summary line: {stdout!r}")
    rc, log = twin.finish()
    check(rc == 0, f"twin-bsl: exit {rc}\n{log}")
    bsl = re.search(r"twin-bsl: ([\d.]+) s: BSL started: software invoke \(RESETLEVEL BOOTLOADERENTRY\)", log)
    check(bsl is not None, f"the image restarted into the BSL by the software invoke:\n{log}")
    # The paths the image controls: the BQ769x FETs, else the fault output (high = paths off; BQ79616, BQ4050).
    paths = re.search(r"before the BSL: (?:FETs off|fault output high) since ([\d.]+) s", log)
    check(paths is not None, f"the paths were off when the BSL started:\n{log}")
    if bsl and paths:
        check(float(paths.group(1)) <= float(bsl.group(1)), "FETs off before the reset")
        print(f"REPORT bmsctl flash --invoke app {preset}: paths off {1000 * (float(bsl.group(1)) - float(paths.group(1))):.1f}"
              f" ms before the BSL started (simulated); the whole run {took:.2f} s of wall time")
    check("application started" in log.split("BSL started: software invoke")[-1],
          "the flashed application started after the BSL session")
    same_frames(preset, out, reset_cause=0x10)  # SYSBSLEXIT


check_name = sys.argv[1]
if check_name.startswith("flash-lp-"):
    c_flash(check_name[len("flash-"):])
elif check_name.startswith("invoke-app-lp-"):
    c_invoke_app(check_name[len("invoke-app-"):])
else:
    {
        "report": c_report,
        "wrong-password": c_wrong_password,
        "no-answer": c_no_answer,
        "reply-crc": c_reply_crc,
        "dropped-byte": c_dropped_byte,
        "cut": c_cut,
        "nonmain": lambda: c_outside(0x41C0, "NONMAIN flash (0x41C00000..0x41C003FF, the boot and BSL configuration)"),
        "sram": lambda: c_outside(0x2020, "SRAM (0x20000000..; a load segment without a flash load address?)"),
        "other-chip": c_other_chip,
        "missing-port": c_missing_port,
        "busy-port": c_busy_port,
        "crc-mismatch": c_crc_mismatch,
        "verify-only": c_verify_only,
        "invoke-button": c_invoke_button,
        "password-file": c_password_file,
        "invoke-app-host": c_invoke_app_host,
        "flash-target": c_flash_target,
        "keeps-data": c_keeps_data,
    }[check_name]()
print(f"{check_name}: {'FAILED' if failures else 'ok'}")
sys.exit(1 if failures else 0)
