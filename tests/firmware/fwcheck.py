#!/usr/bin/env python3
"""Checks a firmware ELF of this project: vector table, forbidden runtime symbols, size budgets and the
statically measured worst-case stack. Python 3 standard library only; reads the ELF itself (no pyelftools)
and asks arm-none-eabi-objdump / arm-none-eabi-c++filt only for what ELF tables do not hold.

Subcommands (each prints its figures as lines starting with "REPORT " and exits non-zero on a failure):
  elf     --elf E --sram-base B --sram-size S --flash-size F --handler NAME:IRQ ...
  stack   --elf E --ci-root DIR --reserved N [--objdump P] [--cxxfilt P]
  budget  --elf E --ci-root DIR --flash-budget N --sram-budget N [--objdump P] [--cxxfilt P]

Stack method (see README.md next to this file): per-function frame sizes from GCC's -fcallgraph-info=su
(.ci) and, for functions compiled without it (libgcc, newlib), from their prologue (PUSH / SUB SP); call
edges from the .ci files and, for functions without one, from BL instructions. An indirect call is resolved
by reading the source at the call's line:column: a call through a member named like a function the image
contains (a virtual `doStart(...)`, `run(...)`) may reach every address-taken function of that name; any
other indirect call (a function pointer) may reach every address-taken function that is not a virtual
member (virtual = labelled so in the .ci, or listed in a vtable). Worst case = thread path
from Reset_Handler + one exception frame + the deepest interrupt handler (all interrupts run at one NVIC
priority, so they do not nest) + one frame + the deepest fault handler (HardFault may hit inside a handler).
Recursion through direct calls, or dynamic frames, fail the check.
"""

import argparse
import glob
import os
import re
import struct
import subprocess
import sys

# ---------------------------------------------------------------------------------------------------------
# ELF32 little-endian reader


class Elf:
    def __init__(self, path):
        with open(path, "rb") as f:
            self.data = f.read()
        d = self.data
        if d[:4] != b"\x7fELF" or d[4] != 1 or d[5] != 1:
            raise SystemExit(f"{path}: not a 32-bit little-endian ELF")
        (e_shoff,) = struct.unpack_from("<I", d, 0x20)
        e_shentsize, e_shnum, e_shstrndx = struct.unpack_from("<HHH", d, 0x2E)
        self.sections = []
        for i in range(e_shnum):
            off = e_shoff + i * e_shentsize
            name, typ, flags, addr, offset, size, link, info, align, entsize = struct.unpack_from("<10I", d, off)
            self.sections.append(dict(name_off=name, type=typ, flags=flags, addr=addr, offset=offset, size=size,
                                      link=link, entsize=entsize))
        shstr = self.sections[e_shstrndx]
        for s in self.sections:
            s["name"] = self._cstr(shstr["offset"] + s["name_off"])
        self.symbols = []
        for s in self.sections:
            if s["type"] != 2:  # SHT_SYMTAB
                continue
            strtab = self.sections[s["link"]]
            for i in range(s["size"] // 16):
                name, value, size, info, other, shndx = struct.unpack_from("<IIIBBH", d, s["offset"] + 16 * i)
                self.symbols.append(dict(name=self._cstr(strtab["offset"] + name), value=value, size=size,
                                         type=info & 0xF, bind=info >> 4, shndx=shndx))

    def _cstr(self, off):
        end = self.data.index(b"\0", off)
        return self.data[off:end].decode("utf-8", "replace")

    def section(self, name):
        for s in self.sections:
            if s["name"] == name:
                return s
        return None

    def words(self, section):
        return struct.unpack_from(f"<{section['size'] // 4}I", self.data, section["offset"])

    def functions(self):
        """Defined function symbols: name -> list of (address without Thumb bit, size, bind)."""
        out = {}
        for sym in self.symbols:
            if sym["type"] == 2 and sym["shndx"] != 0:  # STT_FUNC, defined
                out.setdefault(sym["name"], []).append((sym["value"] & ~1, sym["size"], sym["bind"]))
        return out

    def sizes(self):
        """Berkeley sizes as arm-none-eabi-size reports them: text, data, bss."""
        text = data = bss = 0
        for s in self.sections:
            if not s["flags"] & 0x2:  # SHF_ALLOC
                continue
            if s["type"] == 8:  # SHT_NOBITS
                bss += s["size"]
            elif s["flags"] & 0x1:  # SHF_WRITE
                data += s["size"]
            else:
                text += s["size"]
        return text, data, bss


def report(line):
    print("REPORT " + line, flush=True)


# ---------------------------------------------------------------------------------------------------------
# elf: vector table and forbidden symbols

FORBIDDEN = [
    (re.compile(r"^(_?malloc|_?free|_?calloc|_?realloc|_malloc_r|_free_r|_calloc_r|_realloc_r|_sbrk|_sbrk_r)$"),
     "heap allocator"),
    (re.compile(r"^_Zn[wa]"), "operator new"),
    (re.compile(r"^_Zd[la]"), "operator delete"),
    (re.compile(r"^__cxa_"), "C++ runtime (__cxa_*)"),
    (re.compile(r"^(_Unwind_|__gxx_personality|__aeabi_unwind_cpp_pr)"), "exception unwinding"),
    (re.compile(r"^(printf|sprintf|snprintf|vsnprintf|_printf_r|_vfprintf_r|_svfprintf_r)$"), "printf"),
    (re.compile(r"^(__aeabi_[fd](add|sub|mul|div|cmp\w*)|__addsf3|__adddf3|__mulsf3|__muldf3|__divsf3|__divdf3)$"),
     "floating point"),
]


def cmd_elf(args):
    elf = Elf(args.elf)
    ok = True
    funcs = elf.functions()
    image = os.path.splitext(os.path.basename(args.elf))[0]

    def fail(msg):
        nonlocal ok
        ok = False
        print("FAIL: " + msg)

    vec = elf.section(".isr_vector")
    if vec is None or vec["addr"] != 0 or vec["size"] < 48 * 4:
        raise SystemExit("FAIL: no 48-entry .isr_vector at address 0")
    v = elf.words(vec)
    sram_top = args.sram_base + args.sram_size
    if v[0] != sram_top:
        fail(f"initial SP 0x{v[0]:08x} is not the top of SRAM 0x{sram_top:08x}")
    reset = v[1]
    if not reset & 1:
        fail(f"reset vector 0x{reset:08x} is not a Thumb address")
    if not (reset & ~1) < args.flash_size:
        fail(f"reset vector 0x{reset:08x} is outside flash (0..0x{args.flash_size:x})")
    if funcs.get("Reset_Handler", [(None,)])[0][0] != reset & ~1:
        fail("reset vector does not point to Reset_Handler")
    default = funcs.get("Default_Handler", [(None,)])[0][0]
    if default is None:
        fail("no Default_Handler symbol")
    for i in range(1, 48):
        if v[i] != 0 and (not v[i] & 1 or (v[i] & ~1) >= args.flash_size):
            fail(f"vector {i} = 0x{v[i]:08x} is not a Thumb address in flash")
    checked = []
    for item in args.handler:
        name, irq = item.rsplit(":", 1)
        irq = int(irq)
        entry = v[16 + irq] & ~1
        defs = funcs.get(name)
        if not defs:
            fail(f"IRQ {irq}: no function {name} in the image")
            continue
        addr, _, bind = defs[0]
        if bind != 1:  # STB_GLOBAL (the weak alias of Default_Handler has STB_WEAK)
            fail(f"IRQ {irq}: {name} is only the weak default alias, no driver defines it")
        if entry != addr:
            fail(f"IRQ {irq}: vector 0x{entry:08x} is not {name} (0x{addr:08x})")
        if entry == default:
            fail(f"IRQ {irq}: vector points to Default_Handler")
        checked.append(f"{name}@{irq}")
    bad = []
    for sym in elf.symbols:
        if sym["shndx"] == 0 and sym["name"] == "":
            continue
        for pattern, what in FORBIDDEN:
            if pattern.search(sym["name"]):
                bad.append(f"{sym['name']} ({what})")
    if bad:
        fail("forbidden symbols: " + ", ".join(sorted(set(bad))))
    report(f"elf.{image}.initial_sp=0x{v[0]:08x} reset=0x{reset:08x} handlers={','.join(checked)} "
           f"forbidden_symbols={len(set(bad))}")
    return 0 if ok else 1


# ---------------------------------------------------------------------------------------------------------
# stack analysis

CI_NODE = re.compile(r'^node: \{ title: "([^"]+)" label: "([^"]*)"')
CI_EDGE = re.compile(r'^edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)" label: "([^"]*)"')
CI_BYTES = re.compile(r"\\n(\d+) bytes \(([a-z,]+)\)")
STB_WEAK = 2  # ELF symbol binding
EXCEPTION_FRAME = 32 + 4  # 8 stacked words + up to 4 bytes of alignment padding (ARMv6-M B1.5.7)


def local_name(title):
    """GCC prefixes the .ci titles of file-local functions with their source path: '/a/b.cpp:_ZN..'."""
    return title.rsplit(":", 1)[1] if "/" in title and ":" in title else title


def unqualified(demangled):
    """'virtual void a::B::doStart(std::span<x>, y) const' -> 'doStart'."""
    depth = 0
    cut = len(demangled)
    for i, ch in enumerate(demangled):
        if ch == "<":
            depth += 1
        elif ch == ">":
            depth -= 1
        elif ch == "(" and depth == 0:
            cut = i
            break
    head = demangled[:cut]
    if head.endswith("operator()"):
        return "operator()"
    return re.split(r"::|\s", head)[-1]


class CallGraph:
    def __init__(self, elf, elf_path, ci_root, objdump, cxxfilt):
        self.elf = elf
        self.elf_path = elf_path
        self.ci_root = os.path.abspath(ci_root)
        self.errors = []
        self.funcs = elf.functions()
        self.addr_to_name = {}
        for name, defs in self.funcs.items():
            for addr, _, _ in defs:
                self.addr_to_name.setdefault(addr, name)
        self.thumb = {addr | 1: name for addr, name in self.addr_to_name.items()}  # function pointer -> name
        self.frame = {}  # name -> bytes
        self.dynamic = set()
        self.edges = {}  # name -> set of callee names
        self.indirect = {}  # name -> list of "file:line:col"
        self.demangled = {}
        self.virtual = set()
        self.source = {}  # name -> "ci" or "disassembly"
        for path in sorted(glob.glob(os.path.join(ci_root, "**", "*.ci"), recursive=True)):
            self._read_ci(path)
        missing = [n for n in self.funcs if n not in self.frame]
        if missing:
            self._read_disassembly(objdump, missing)
        self._demangle_rest(cxxfilt)
        self.address_taken = self._address_taken()
        self.virtual |= self._vtable_entries()
        self.by_name = {}
        for name in self.funcs:
            self.by_name.setdefault(unqualified(self.demangled.get(name, name)), set()).add(name)

    def _read_ci(self, path):
        with open(path, encoding="utf-8", errors="replace") as f:
            for line in f:
                m = CI_NODE.match(line)
                if m:
                    title, label = m.groups()
                    if title == "__indirect_call":
                        continue
                    title = local_name(title)
                    signature = label.split("\\n")[0].strip()
                    self.demangled.setdefault(title, signature)
                    if signature.startswith("virtual "):
                        self.virtual.add(title)
                    b = CI_BYTES.search(label)
                    if b and title in self.funcs:
                        size, kind = int(b.group(1)), b.group(2)
                        self.frame[title] = max(self.frame.get(title, 0), size)
                        self.source[title] = "ci"
                        if kind.startswith("dynamic") and "bounded" not in kind:
                            self.dynamic.add(title)
                    continue
                m = CI_EDGE.match(line)
                if m:
                    src, dst, label = m.groups()
                    src, dst = local_name(src), local_name(dst)
                    if src not in self.funcs:
                        continue
                    if dst == "__indirect_call":
                        self.indirect.setdefault(src, []).append(label)
                    else:
                        self.edges.setdefault(src, set()).add(dst)

    def _read_disassembly(self, objdump, names):
        wanted = set(names)
        out = subprocess.run([objdump, "-d", self.elf_path], capture_output=True, text=True, check=True).stdout
        current = None
        first = 0
        for line in out.splitlines():
            m = re.match(r"^([0-9a-f]+) <([^>]+)>:$", line)
            if m:
                current = m.group(2) if m.group(2) in wanted else None
                first = 0
                if current is not None:
                    self.frame.setdefault(current, 0)
                    self.source[current] = "disassembly"
                continue
            if current is None:
                continue
            m = re.match(r"^\s+[0-9a-f]+:\s+(?:[0-9a-f]{4}\s+)+\s*(\S+)\s*(.*)$", line)
            if not m:
                continue
            op, operands = m.groups()
            first += 1
            if first <= 4 and op == "push":
                self.frame[current] += 4 * len(operands.split("}")[0].strip("{ ").split(","))
            elif first <= 6 and op == "sub" and operands.startswith("sp"):
                n = re.search(r"#(\d+)", operands)
                if n:
                    self.frame[current] += int(n.group(1))
            elif op in ("bl", "blx"):
                t = re.search(r"<([^>+]+)>", operands)
                if t:
                    self.edges.setdefault(current, set()).add(t.group(1))
                elif op == "blx":
                    self.indirect.setdefault(current, []).append("?")

    def _demangle_rest(self, cxxfilt):
        rest = [n for n in self.funcs if n not in self.demangled]
        if not rest:
            return
        try:
            out = subprocess.run([cxxfilt], input="\n".join(rest), capture_output=True, text=True, check=True).stdout
            for name, dem in zip(rest, out.splitlines()):
                self.demangled[name] = dem
        except (OSError, subprocess.CalledProcessError):
            for name in rest:
                self.demangled[name] = name

    def _address_taken(self):
        """Functions whose Thumb address appears as a data word outside the vector table: vtable entries,
        function pointers in literal pools, initialised data."""
        taken = set()
        for s in self.elf.sections:
            if not s["flags"] & 0x2 or s["type"] == 8 or s["name"] == ".isr_vector":
                continue
            for w in self.elf.words(dict(s, size=s["size"] & ~3)):
                if w in self.thumb:
                    taken.add(self.thumb[w])
        return taken

    def _vtable_entries(self):
        """Functions listed in a vtable (_ZTV* objects): virtual members and their thunks. GCC's .ci label
        says "virtual" for ordinary classes but not for members of class templates, so the vtables are the
        reliable source. A plain function pointer (Notify::fn) can never hold one of these."""
        entries = set()
        for sym in self.elf.symbols:
            if not sym["name"].startswith("_ZTV") or sym["type"] != 1 or sym["shndx"] >= len(self.elf.sections):
                continue
            sec = self.elf.sections[sym["shndx"]]
            if sec["type"] == 8:  # NOBITS: no contents
                continue
            start = sec["offset"] + (sym["value"] - sec["addr"])
            for i in range(sym["size"] // 4):
                (w,) = struct.unpack_from("<I", self.elf.data, start + 4 * i)
                if w in self.thumb:
                    entries.add(self.thumb[w])
        return entries

    def _source_path(self, path):
        """The file a .ci label names. A compiler cache may have recorded a path relative to the build that
        first compiled it (ccache's base_dir): then the longest tail of it found under the source tree (the
        build folder's parents) is the file."""
        if os.path.exists(path):
            return path
        parts = [p for p in os.path.normpath(path).split(os.sep) if p not in ("", "..", ".")]
        roots = [self.ci_root, os.path.dirname(self.ci_root), os.path.dirname(os.path.dirname(self.ci_root))]
        for k in range(len(parts)):
            for root in roots:
                candidate = os.path.join(root, *parts[k:])
                if os.path.exists(candidate):
                    return candidate
        return None

    def indirect_targets(self, label):
        """Candidates for an indirect call at `label` (path:line:col, the column of the call's '(')."""
        name = None
        m = re.match(r"^(.*):(\d+):(\d+)$", label)
        source = self._source_path(m.group(1)) if m else None
        if source is None:
            # The call's source cannot be read: it may call anything address-taken, virtual members included.
            return set(self.address_taken), None
        if m:
            with open(source, encoding="utf-8", errors="replace") as f:
                lines = f.read().splitlines()
            line_no, col = int(m.group(2)), int(m.group(3))
            if 0 < line_no <= len(lines):
                text = lines[line_no - 1][: col - 1].rstrip()
                ident = re.search(r"([A-Za-z_][A-Za-z0-9_]*)$", text)
                if ident:
                    name = ident.group(1)
        named = self.by_name.get(name, set()) & self.address_taken if name else set()
        if named:
            return named, name
        # A call through a plain function pointer (a Notify, a callback member): any address-taken function
        # except virtual member functions, which the firmware only reaches through virtual calls.
        return self.address_taken - self.virtual, name

    def worst(self, root):
        """Worst-case stack from `root` down, and its path. A cycle that goes through an indirect edge is
        ignored (the over-approximated candidate sets create such false cycles: a function reached through a
        pointer may call directly into one already on the path; the firmware has no recursion); a cycle of
        direct calls only is an error. `direct` is the part of the path since its last indirect edge."""
        memo = {}

        def visit(name, path, direct):
            if name in memo:
                return memo[name]
            frame = self.frame.get(name)
            if frame is None:
                if name not in self.funcs:
                    return 0, [name + "?"], True  # not in the image (inlined away or weak undefined)
                frame = 0
            if name in self.dynamic:
                self.errors.append(f"{name}: dynamic stack frame")
            best, best_path, clean = 0, [], True
            on_path = path | {name}
            on_direct = direct | {name}
            for callee in sorted(self.edges.get(name, ())):  # sorted: the same path on every run
                if callee in on_direct:
                    self.errors.append(f"recursion: {name} -> {callee}")
                    continue
                if callee in on_path:  # the cycle goes through an indirect edge: a false one
                    clean = False
                    continue
                depth, sub, c = visit(callee, on_path, on_direct)
                clean &= c
                if depth > best:
                    best, best_path = depth, sub
            for label in self.indirect.get(name, ()):
                targets, ident = self.indirect_targets(label)
                for callee in sorted(targets):
                    if callee in on_path:
                        clean = False
                        continue
                    depth, sub, c = visit(callee, on_path, frozenset())
                    clean &= c
                    if depth > best:
                        best, best_path = depth, [f"[{ident or 'fn ptr'}]"] + sub
            result = (frame + best, [f"{self.demangled.get(name, name).split('(')[0]}:{frame}"] + best_path, clean)
            if clean:
                memo[name] = result
            return result

        depth, path, _ = visit(root, frozenset(), frozenset())
        return depth, path

    def deepest(self, roots):
        """The deepest worst() over `roots` (None entries skipped; ties go to the first in sorted order)."""
        best, best_path = 0, []
        for name in sorted(n for n in roots if n):
            d, p = self.worst(name)
            if d > best:
                best, best_path = d, p
        return best, best_path


def analyse_stack(args):
    elf = Elf(args.elf)
    graph = CallGraph(elf, args.elf, args.ci_root, args.objdump, args.cxxfilt)
    v = elf.words(elf.section(".isr_vector"))
    reset = graph.addr_to_name[v[1] & ~1]
    thread, thread_path = graph.worst(reset)
    fault_names = {graph.addr_to_name.get(v[i] & ~1) for i in (2, 3) if v[i]}
    isr_names = set()
    for i in range(4, 48):
        if v[i]:
            isr_names.add(graph.addr_to_name.get(v[i] & ~1))
    isr, isr_path = graph.deepest(isr_names - fault_names)
    fault, fault_path = graph.deepest(fault_names)
    total = thread + EXCEPTION_FRAME + isr + EXCEPTION_FRAME + fault
    # The entry points must come with GCC's call graph: a prologue alone hides every pointer and virtual call.
    # Under link-time optimisation the code (and so its .ci) is generated by the link, not by the compiles.
    # The default handler (the address weak vector aliases share) is plain code outside LTO, read from its
    # disassembly like libgcc (ccache does not keep .ci files).
    weak_alias_at = {addr for defs in graph.funcs.values() for addr, _, bind in defs if bind == STB_WEAK}
    for root in sorted(({reset} | isr_names | fault_names) - {None}):
        addrs = {addr for addr, _, _ in graph.funcs.get(root, [])}
        if graph.source.get(root) != "ci" and not addrs & weak_alias_at:
            graph.errors.append(f"{root}: no call graph (.ci) for this entry point: was the image's link given "
                                "-fcallgraph-info=su (LTO) or its objects compiled with it?")
    errors = sorted(set(graph.errors))
    from_disassembly = sorted(n for n, s in graph.source.items() if s == "disassembly" and n in graph.funcs)
    return dict(total=total, thread=thread, isr=isr, fault=fault, thread_path=thread_path, isr_path=isr_path,
                fault_path=fault_path, errors=errors, from_disassembly=from_disassembly,
                functions=len(graph.frame))


def print_stack(image, s):
    print(f"stack {image}: thread {s['thread']} B: " + " > ".join(s["thread_path"]))
    print(f"stack {image}: deepest interrupt {s['isr']} B: " + " > ".join(s["isr_path"]))
    print(f"stack {image}: deepest fault handler {s['fault']} B: " + " > ".join(s["fault_path"]))
    if s["from_disassembly"]:
        print(f"stack {image}: frames from disassembly (no .ci): " + ", ".join(s["from_disassembly"]))


def cmd_stack(args):
    image = os.path.splitext(os.path.basename(args.elf))[0]
    s = analyse_stack(args)
    print_stack(image, s)
    report(f"stack.{image}.worst_case={s['total']} (thread {s['thread']} + frame {EXCEPTION_FRAME} + interrupt "
           f"{s['isr']} + frame {EXCEPTION_FRAME} + fault {s['fault']}; reserved {args.reserved})")
    ok = True
    for e in s["errors"]:
        print("FAIL: " + e)
        ok = False
    if s["total"] > args.reserved:
        print(f"FAIL: worst-case stack {s['total']} B exceeds the {args.reserved} B reservation")
        ok = False
    if s["functions"] < 10:
        print("FAIL: fewer than 10 functions with stack data: was the image built with -fcallgraph-info=su?")
        ok = False
    return 0 if ok else 1


def cmd_budget(args):
    image = os.path.splitext(os.path.basename(args.elf))[0]
    text, data, bss = Elf(args.elf).sizes()
    s = analyse_stack(args)
    flash = text + data
    sram = data + bss + s["total"]
    report(f"size.{image}.flash={flash} (text {text} + data {data}; budget {args.flash_budget})")
    report(f"size.{image}.sram={sram} (data {data} + bss {bss} + worst-case stack {s['total']}; "
           f"budget {args.sram_budget})")
    ok = True
    if flash > args.flash_budget:
        print(f"FAIL: flash {flash} B over the {args.flash_budget} B budget")
        ok = False
    if sram > args.sram_budget:
        print(f"FAIL: SRAM {sram} B over the {args.sram_budget} B budget")
        ok = False
    return 0 if ok else 1


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    e = sub.add_parser("elf")
    e.add_argument("--elf", required=True)
    e.add_argument("--sram-base", type=lambda x: int(x, 0), required=True)
    e.add_argument("--sram-size", type=lambda x: int(x, 0), required=True)
    e.add_argument("--flash-size", type=lambda x: int(x, 0), required=True)
    e.add_argument("--handler", action="append", default=[])
    for name in ("stack", "budget"):
        s = sub.add_parser(name)
        s.add_argument("--elf", required=True)
        s.add_argument("--ci-root", required=True)
        s.add_argument("--objdump", default="arm-none-eabi-objdump")
        s.add_argument("--cxxfilt", default="arm-none-eabi-c++filt")
        if name == "stack":
            s.add_argument("--reserved", type=int, required=True)
        else:
            s.add_argument("--flash-budget", type=int, required=True)
            s.add_argument("--sram-budget", type=int, required=True)
    args = p.parse_args()
    return {"elf": cmd_elf, "stack": cmd_stack, "budget": cmd_budget}[args.cmd](args)


if __name__ == "__main__":
    sys.exit(main())
