"""Public API of the all-atom builder (docs/builder.md).

    from mdbridge.build import build_duplex, check_chemistry, write_pdb
    s = build_duplex("CGCGAATTCGCG", origins, R)          # linear
    s = build_duplex(seq, origins, R, periodic_box=L)     # one period along z
    print(check_chemistry(s)); write_pdb("out.pdb", s)
"""
from mdbridge.builder.chemistry import ChemistryReport, check_chemistry
from mdbridge.builder.duplex import base_frames, build_duplex
from mdbridge.builder.frames import ideal_frames
from mdbridge.builder.structure import Structure
from mdbridge.geometry.steps import frames_from_steps
from mdbridge.pdbio import read_pdb, write_pdb

__all__ = ["ChemistryReport", "Structure", "base_frames", "build_duplex", "check_chemistry",
           "frames_from_steps", "ideal_frames", "read_pdb", "write_pdb"]
