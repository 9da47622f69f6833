"""Opening a board that bms-sim serves on a pseudo-terminal (`bms-sim ... --slcan pty`), shared by the tests.

start(sim, *args) runs `sim *args` (args hold `--slcan pty`) with its stdout and stderr piped (stdout= takes
another, e.g. subprocess.DEVNULL; cwd= the folder to run in) and returns (proc, path): bms-sim names its
terminal on its first stderr line ("bms-sim: SLCAN on /dev/pts/N ..."); without that line the process is killed
and the test fails.
open_bus(path) opens python-can's slcan interface on it at 500 kbit/s (python-can 4.1 sends C, S6 and O on
opening; the board answers BEL, CR, CR, and bms-sim starts the board only once O arrives).
FIRST_FRAME_S bounds the wait for the first frame: the board starts only when the reader has opened the channel,
which may take long on a loaded machine.
"""
import subprocess

from bms_sim_acceptance import fail

FIRST_FRAME_S = 20.0


def start(sim, *args, stdout=subprocess.PIPE, cwd=None):
    proc = subprocess.Popen([sim, *args], cwd=cwd, stdout=stdout, stderr=subprocess.PIPE, text=True)
    first = proc.stderr.readline()
    if " on /dev/" not in first:
        proc.kill()
        fail(f"--slcan pty did not print its terminal: {first!r}")
    return proc, first.split(" on ")[1].split()[0]


def open_bus(path):
    import can  # python3-can (Debian); imported here so the callers' other checks do not need it

    return can.Bus(interface="slcan", channel=path, bitrate=500000, sleep_after_open=0)
