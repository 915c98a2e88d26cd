#!/usr/bin/env python3
"""Flash and static RAM of a 32-bit ELF (the firmware), from its section headers.

Flash: every allocated section with file contents that is loaded from flash (.vector_table,
.text, .rodata, and the initial values of .data). Static RAM: .data, .bss and .uninit
(the stack comes on top). Prints `flash_bytes=N ram_bytes=M` and, with -v, each section.
Written by hand because the image needs only the ELF header and the section table; the
Debian packages of binutils read ARM images only in their cross variants.
"""
import struct
import sys


def sections(path):
    data = open(path, "rb").read()
    if data[:4] != b"\x7fELF" or data[4] != 1:
        raise SystemExit(f"{path}: not a 32-bit ELF file")
    (shoff,) = struct.unpack_from("<I", data, 0x20)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x2E)
    heads = [struct.unpack_from("<IIIIIIIIII", data, shoff + i * shentsize) for i in range(shnum)]
    strtab = heads[shstrndx]
    names = data[strtab[4] : strtab[4] + strtab[5]]
    for name, typ, flags, addr, off, size, *_ in heads:
        end = names.index(b"\0", name)
        yield names[name:end].decode(), typ, flags, addr, size


def main():
    verbose = "-v" in sys.argv
    path = [a for a in sys.argv[1:] if a != "-v"][0]
    flash = ram = 0
    SHF_ALLOC, SHT_NOBITS = 0x2, 8
    for name, typ, flags, addr, size in sections(path):
        if not flags & SHF_ALLOC or size == 0:
            continue
        in_ram = addr >= 0x20000000
        if not in_ram:
            flash += size
        else:
            ram += size
            if typ != SHT_NOBITS:
                flash += size  # .data's initial values live in flash too
        if verbose:
            print(f"{name:20} addr={addr:#010x} size={size}", file=sys.stderr)
    print(f"flash_bytes={flash} ram_bytes={ram}")


main()
