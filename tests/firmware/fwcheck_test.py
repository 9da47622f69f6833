#!/usr/bin/env python3
"""Unit tests of fwcheck.py: synthetic ELF files and call graphs on which each check must pass or fail."""

import contextlib
import io
import os
import struct
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fwcheck  # noqa: E402

SRAM_TOP = 0x20001000


def build_elf(path, vectors, symbols, extra_words=()):
    """A minimal ELF32: .isr_vector (address 0) with `vectors`, .text (address 0x100) holding `extra_words`
    (as literal data), and a symbol table. symbols: (name, address, type, bind[, size])."""
    shstr = b"\0.isr_vector\0.text\0.symtab\0.strtab\0.shstrtab\0"
    strtab = b"\0"
    symtab = b"\0" * 16
    for name, addr, typ, bind, *size in symbols:
        off = len(strtab)
        strtab += name.encode() + b"\0"
        shndx = 1 if addr < 0x100 else 2
        symtab += struct.pack("<IIIBBH", off, addr, size[0] if size else 4, (bind << 4) | typ, 0, shndx)
    vec = struct.pack(f"<{len(vectors)}I", *vectors)
    text = struct.pack(f"<{len(extra_words)}I", *extra_words) if extra_words else b"\0\0\0\0"
    blobs = [vec, text, symtab, strtab, shstr]
    offsets = []
    pos = 52
    for b in blobs:
        offsets.append(pos)
        pos += len(b)
    shoff = (pos + 3) & ~3
    body = b"".join(blobs)
    sh = b"\0" * 40
    sh += struct.pack("<10I", 1, 1, 0x6, 0x0, offsets[0], len(vec), 0, 0, 4, 0)  # .isr_vector
    sh += struct.pack("<10I", 13, 1, 0x6, 0x100, offsets[1], len(text), 0, 0, 4, 0)  # .text
    sh += struct.pack("<10I", 19, 2, 0, 0, offsets[2], len(symtab), 4, 1, 4, 16)  # .symtab -> .strtab
    sh += struct.pack("<10I", 27, 3, 0, 0, offsets[3], len(strtab), 0, 0, 1, 0)  # .strtab
    sh += struct.pack("<10I", 35, 3, 0, 0, offsets[4], len(shstr), 0, 0, 1, 0)  # .shstrtab
    header = b"\x7fELF\x01\x01\x01" + b"\0" * 9
    header += struct.pack("<HHIIIIIHHHHHH", 2, 40, 1, 0x41, 0, shoff, 0x5000000, 52, 0, 0, 40, 6, 5)
    with open(path, "wb") as f:
        f.write(header + body + b"\0" * (shoff - pos) + sh)


FUNC, OBJECT, GLOBAL, WEAK, LOCAL = 2, 1, 1, 2, 0


def good_image(handler_bind=GLOBAL, i2c_vector=None, extra_symbols=(), sp=SRAM_TOP):
    reset, default, hardfault, i2c = 0xC0, 0xD0, 0xD8, 0xE0
    vectors = [sp, reset | 1, default | 1, hardfault | 1] + [0] * 7 + [default | 1, 0, 0, default | 1, default | 1]
    vectors += [default | 1] * 32
    vectors[16 + 24] = (i2c_vector if i2c_vector is not None else i2c) | 1
    symbols = [("Reset_Handler", reset | 1, FUNC, GLOBAL), ("Default_Handler", default | 1, FUNC, GLOBAL),
               ("HardFault_Handler", hardfault | 1, FUNC, GLOBAL), ("I2C0_IRQHandler", i2c | 1, FUNC, handler_bind)]
    return vectors, symbols + list(extra_symbols)


class ElfCheckTest(unittest.TestCase):
    def run_elf(self, vectors, symbols):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "img.elf")
            build_elf(path, vectors, symbols)
            args = fwcheck.argparse.Namespace(elf=path, sram_base=0x20000000, sram_size=0x1000, flash_size=0x10000,
                                              handler=["I2C0_IRQHandler:24"])
            out = io.StringIO()
            with contextlib.redirect_stdout(out):
                rc = fwcheck.cmd_elf(args)
            return rc, out.getvalue()

    def test_good_image_passes(self):
        rc, out = self.run_elf(*good_image())
        self.assertEqual(rc, 0, out)
        self.assertIn("REPORT elf.img.initial_sp=0x20001000", out)

    def test_initial_sp_not_sram_top_fails(self):
        rc, out = self.run_elf(*good_image(sp=SRAM_TOP - 8))
        self.assertEqual(rc, 1)
        self.assertIn("initial SP", out)

    def test_vector_to_default_handler_fails(self):
        rc, out = self.run_elf(*good_image(i2c_vector=0xD0))
        self.assertEqual(rc, 1)
        self.assertIn("Default_Handler", out)

    def test_weak_handler_fails(self):
        rc, out = self.run_elf(*good_image(handler_bind=WEAK))
        self.assertEqual(rc, 1)
        self.assertIn("weak", out)

    def test_heap_and_cxa_symbols_fail(self):
        rc, out = self.run_elf(*good_image(extra_symbols=[("malloc", 0xF0 | 1, FUNC, GLOBAL),
                                                          ("__cxa_pure_virtual", 0xF8 | 1, FUNC, GLOBAL)]))
        self.assertEqual(rc, 1)
        self.assertIn("malloc", out)
        self.assertIn("__cxa_pure_virtual", out)


class StackAnalysisTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.root = self.dir.name
        # A source file whose line 1 has a virtual call `doWork(` (the paren at column 11) and line 2 a pointer
        # call `fn(` (column 5); GCC labels indirect calls with the column of the paren.
        self.src = os.path.join(self.root, "a.cpp")
        with open(self.src, "w") as f:
            f.write("  x.doWork(1);\n  fn(2);\n")

    def tearDown(self):
        self.dir.cleanup()

    def write_ci(self, name, text):
        with open(os.path.join(self.root, name), "w") as f:
            f.write(text)

    def node(self, title, label, size, virtual=False):
        v = "virtual " if virtual else ""
        return f'node: {{ title: "{title}" label: "{v}void {label}()\\n{self.src}:1:1\\n{size} bytes (static)" }}\n'

    def edge(self, a, b, label="x.cpp:1:1"):
        return f'edge: {{ sourcename: "{a}" targetname: "{b}" label: "{label}" }}\n'

    def analyse(self, nodes, vectors_of, taken=(), vtable=(), objdump="false"):
        """nodes: name -> address. vectors_of: (reset, [isr...]). taken: functions whose address is a data word;
        vtable: those of them (the first len(vtable) words) that form a _ZTV object."""
        reset, isrs = vectors_of
        vectors = [SRAM_TOP, nodes[reset] | 1, 0, 0] + [0] * 12 + [0] * 32
        for i, isr in enumerate(isrs):
            vectors[16 + i] = nodes[isr] | 1
        symbols = [(n, a | 1, FUNC, GLOBAL) for n, a in nodes.items()]
        if vtable:
            assert list(taken[: len(vtable)]) == list(vtable)
            symbols.append(("_ZTVN1a1BE", 0x100, OBJECT, GLOBAL, 4 * len(vtable)))
        path = os.path.join(self.root, "img.elf")
        build_elf(path, vectors, symbols, extra_words=[nodes[t] | 1 for t in taken])
        args = fwcheck.argparse.Namespace(elf=path, ci_root=self.root, objdump=objdump, cxxfilt="false")
        return fwcheck.analyse_stack(args)

    def test_sums_thread_and_deepest_interrupt_with_frames(self):
        self.write_ci("a.ci", self.node("Reset", "Reset", 8) + self.node("main", "main", 24) + self.edge("Reset", "main")
                      + self.node("IsrA", "IsrA", 16) + self.node("IsrB", "IsrB", 40) + self.node("leaf", "leaf", 8)
                      + self.edge("IsrA", "leaf"))
        s = self.analyse({"Reset": 0xC0, "main": 0xC8, "IsrA": 0xD0, "IsrB": 0xD8, "leaf": 0xE0},
                         ("Reset", ["IsrA", "IsrB"]))
        self.assertEqual(s["thread"], 32)
        self.assertEqual(s["isr"], 40)
        self.assertEqual(s["total"], 32 + 40 + 2 * fwcheck.EXCEPTION_FRAME)
        self.assertEqual(s["errors"], [])

    def test_virtual_call_reaches_every_address_taken_function_of_that_name(self):
        self.write_ci("a.ci", self.node("Reset", "Reset", 8)
                      + self.edge("Reset", "__indirect_call", f"{self.src}:1:11")
                      + self.node("A_doWork", "A::doWork", 16, virtual=True)
                      + self.node("B_doWork", "B::doWork", 100, virtual=True)
                      + self.node("other", "C::other", 500, virtual=True))
        s = self.analyse({"Reset": 0xC0, "A_doWork": 0xC8, "B_doWork": 0xD0, "other": 0xD8}, ("Reset", []),
                         taken=["A_doWork", "B_doWork", "other"])
        self.assertEqual(s["thread"], 108)  # B::doWork, not the unrelated 500-byte function

    def test_pointer_call_reaches_non_virtual_address_taken_functions(self):
        self.write_ci("a.ci", self.node("Reset", "Reset", 8)
                      + self.edge("Reset", "__indirect_call", f"{self.src}:2:5")
                      + self.node("thunk", "thunk", 24) + self.node("vfn", "V::run", 400, virtual=True)
                      + self.node("untaken", "untaken", 900))
        s = self.analyse({"Reset": 0xC0, "thunk": 0xC8, "vfn": 0xD0, "untaken": 0xD8}, ("Reset", []),
                         taken=["thunk", "vfn"])
        self.assertEqual(s["thread"], 32)

    def test_pointer_call_skips_vtable_entries_even_without_a_virtual_label(self):
        # GCC labels members of class templates without "virtual"; their vtable still says what they are.
        self.write_ci("a.ci", self.node("Reset", "Reset", 8)
                      + self.edge("Reset", "__indirect_call", f"{self.src}:2:5")
                      + self.node("thunk", "thunk", 24) + self.node("tvfn", "T<int>::run", 400))
        s = self.analyse({"Reset": 0xC0, "thunk": 0xC8, "tvfn": 0xD0}, ("Reset", []),
                         taken=["tvfn", "thunk"], vtable=["tvfn"])
        self.assertEqual(s["thread"], 32)

    def test_a_call_whose_source_is_unreadable_may_reach_virtual_members_too(self):
        # A compiler cache can record a label relative to another build: unreadable, the call is not known to
        # be a plain pointer call, so virtual members count too (they were left out: 448 B instead of 816 B).
        self.write_ci("a.ci", self.node("Reset", "Reset", 8)
                      + self.edge("Reset", "__indirect_call", "../../elsewhere/nowhere.cpp:2:5")
                      + self.node("thunk", "thunk", 24) + self.node("vfn", "V::run", 400, virtual=True))
        s = self.analyse({"Reset": 0xC0, "thunk": 0xC8, "vfn": 0xD0}, ("Reset", []), taken=["thunk", "vfn"])
        self.assertEqual(s["thread"], 408)

    def test_a_label_relative_to_another_build_is_found_under_this_source_tree(self):
        rel = os.path.join("..", "..", "other", "build", "img", "..", "..", os.path.basename(self.src))
        self.write_ci("a.ci", self.node("Reset", "Reset", 8)
                      + self.edge("Reset", "__indirect_call", f"{rel}:2:5")
                      + self.node("thunk", "thunk", 24) + self.node("vfn", "V::run", 400, virtual=True))
        s = self.analyse({"Reset": 0xC0, "thunk": 0xC8, "vfn": 0xD0}, ("Reset", []), taken=["thunk", "vfn"])
        self.assertEqual(s["thread"], 32)  # line 2 is the pointer call `fn(`: virtual members left out

    def test_direct_recursion_is_an_error(self):
        self.write_ci("a.ci", self.node("Reset", "Reset", 8) + self.node("f", "f", 8) + self.node("g", "g", 8)
                      + self.edge("Reset", "f") + self.edge("f", "g") + self.edge("g", "f"))
        s = self.analyse({"Reset": 0xC0, "f": 0xC8, "g": 0xD0}, ("Reset", []))
        self.assertTrue(any("recursion" in e for e in s["errors"]), s["errors"])

    def test_a_cycle_through_a_pointer_call_is_not_recursion(self):
        # s calls a pointer (any address-taken function may be its target, a among them), and a calls s
        # directly: the over-approximated pointer edge closes the cycle, not the firmware (the merged
        # applications' startTimer -> Clock::now -> [fn ptr] -> appInit -> startTimer looked like this).
        self.write_ci("a.ci", self.node("Reset", "Reset", 8) + self.node("s", "s", 16) + self.node("a", "a", 24)
                      + self.edge("Reset", "s") + self.edge("a", "s")
                      + self.edge("s", "__indirect_call", f"{self.src}:2:5"))
        s = self.analyse({"Reset": 0xC0, "s": 0xC8, "a": 0xD0}, ("Reset", []), taken=["a"])
        self.assertEqual(s["errors"], [])
        self.assertEqual(s["thread"], 8 + 16 + 24)

    def test_an_entry_point_without_call_graph_data_is_an_error(self):
        # An LTO image whose link emitted no .ci: the handler's frame would come from its prologue alone and the
        # calls it makes through pointers would be missed (212 B instead of 728 B on lp-mspm0l1306-bq76952).
        self.write_ci("a.ci", self.node("Reset", "Reset", 8))
        s = self.analyse({"Reset": 0xC0, "IsrA": 0xD0}, ("Reset", ["IsrA"]), objdump="true")
        self.assertTrue(any(e.startswith("IsrA: no call graph") for e in s["errors"]), s["errors"])

    def test_ltrans_titles_name_the_linked_functions(self):
        # The link's .ci (ltrans0.ltrans.ci) prefixes every title, global ones too, with its temporary object.
        t = "/tmp/ccX.ltrans0.o:"
        self.write_ci("ltrans0.ltrans.ci", self.node(t + "Reset", "Reset", 8) + self.node(t + "leaf.constprop.0", "leaf", 24)
                      + self.edge(t + "Reset", t + "leaf.constprop.0"))
        s = self.analyse({"Reset": 0xC0, "leaf.constprop.0": 0xC8}, ("Reset", []))
        self.assertEqual(s["thread"], 32)
        self.assertEqual(s["errors"], [])

    def test_dynamic_frame_is_an_error(self):
        self.write_ci("a.ci", f'node: {{ title: "Reset" label: "void Reset()\\nx.cpp:1:1\\n16 bytes (dynamic)" }}\n')
        s = self.analyse({"Reset": 0xC0}, ("Reset", []))
        self.assertTrue(any("dynamic" in e for e in s["errors"]), s["errors"])


if __name__ == "__main__":
    unittest.main(verbosity=2)
