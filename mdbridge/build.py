"""Public API of the all-atom builder (docs/builder.md).

    from mdbridge.build import build_duplex, check_chemistry, write_pdb
    s = build_duplex("CGCGAATTCGCG", origins, R)          # linear
    s = build_duplex(seq, origins, R, periodic_box=L)     # one period along z
    print(check_chemistry(s)); write_pdb("out.pdb", s)
"""
from mdbridge.builder.chemistry import ChemistryReport, check_chemistry  # noqa: F401
from mdbridge.builder.duplex import base_frames, build_duplex  # noqa: F401
from mdbridge.builder.frames import frames_from_steps, ideal_frames  # noqa: F401
from mdbridge.builder.structure import Structure  # noqa: F401
from mdbridge.pdbio import read_pdb, write_pdb  # noqa: F401
