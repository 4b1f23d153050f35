"""All-atom DNA duplexes from base-pair frames (3DNA rebuild's method) and their
chemistry checks (docs/builder.md).

    from mdbridge.md.builder import build_duplex, check_chemistry, write_pdb
    s = build_duplex("CGCGAATTCGCG", origins, R)          # linear
    s = build_duplex(seq, origins, R, periodic_box=L)     # one period along z
    print(check_chemistry(s)); write_pdb("out.pdb", s)
"""
from mdbridge.geometry.steps import frames_from_steps
from mdbridge.md.pdbio import read_pdb, write_pdb

from .chemistry import ChemistryReport, check_chemistry
from .duplex import base_frames, build_duplex
from .frames import ideal_frames
from .structure import Structure

__all__ = ["ChemistryReport", "Structure", "base_frames", "build_duplex", "check_chemistry",
           "frames_from_steps", "ideal_frames", "read_pdb", "write_pdb"]
