#!/usr/bin/python3
"""Decodes the frames printed by can_vectors with the generated DBC files, using Debian's python3-canmatrix
(an independent DBC reader), and compares every signal with the value worked out by hand. An expected value
"na" means the DBC must name the raw value "not_available" (VAL_) and place it outside the signal's range.

usage: dbc_check.py <vectors-program> <native.dbc> <ti.dbc>
Exit 0 when every frame decodes to exactly the expected signals and values."""
import subprocess
import sys

import canmatrix
import canmatrix.formats


def main():
    program, native, ti = sys.argv[1:4]
    dbs = {"native": canmatrix.formats.loadp_flat(native), "ti": canmatrix.formats.loadp_flat(ti)}
    for name, db in dbs.items():
        print(f"{name}: {len(db.frames)} messages loaded")
        if not db.frames:
            print(f"FAIL: {name} DBC has no messages")
            return 1
    lines = subprocess.run([program], check=True, capture_output=True, text=True).stdout.splitlines()
    failures = 0
    for line in lines:
        layout, ident, data, *expect = line.split()
        frame = dbs[layout].frame_by_id(canmatrix.ArbitrationId(int(ident, 16)))
        if frame is None:
            print(f"FAIL: {layout} has no message with id 0x{ident}")
            failures += 1
            continue
        signals = frame.decode(bytearray.fromhex(data))
        decoded = {k: float(v.phys_value) for k, v in signals.items()}
        wanted = dict(item.split("=") for item in expect)
        for signal, value in wanted.items():
            got = decoded.get(signal)
            if value == "na":
                s = signals.get(signal)
                named = s.signal.values.get(int(s.raw_value)) if s is not None else None
                in_range = s is not None and s.signal.min <= decoded[signal] <= s.signal.max
                if named != "not_available" or in_range:
                    print(f"FAIL: {frame.name} {signal}: raw {s and s.raw_value} is named {named!r} and "
                          f"{'inside' if in_range else 'outside'} the signal's range (frame {data})")
                    failures += 1
            elif got is None or abs(got - float(value)) > 1e-6:
                print(f"FAIL: {frame.name} {signal}: decoded {got}, expected {value} (frame {data})")
                failures += 1
        extra = set(decoded) - set(wanted)
        if extra:
            print(f"FAIL: {frame.name}: unexpected signals {sorted(extra)}")
            failures += 1
        print(f"{frame.name} {data}: {len(wanted)} signals checked")
    if failures:
        return 1
    print(f"all {len(lines)} frames decode as expected")
    return 0


if __name__ == "__main__":
    sys.exit(main())
