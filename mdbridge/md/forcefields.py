"""The force fields dnarod builds with, and every fact of each it relies on: one home.

A `ForceField` holds what pdb2gmx needs (the folder, the extra options, the answers to
its terminus prompts, whether the strands need a private copy whose dna.r2b makes every
residue a middle one), how the builder's atom names become the force field's, the
phosphate's non-bridging oxygens, the bond constants the builder and the summary use,
the hydrogen templates, the water models and the ions. Each number is read from the
GROMACS folder named in its comment (/usr/share/gromacs/top/<name>.ff on Debian);
tests/python/test_forcefields.py holds the registry against those files.

The builder's own atoms (dna_models' nucleotide templates) carry CHARMM27 names and
geometry: `BUILDER` is that force field, `renames` says how another one spells them.

Adding a force field: docs/builder.md, "Adding a force field".
"""
from __future__ import annotations

from dataclasses import dataclass

from dna_models.errors import InputError
from dna_models.nucleotides import CHARMM_RESNAME
from dna_models.templates import H_DATA


@dataclass(frozen=True)
class Bond:
    """A harmonic bond of the force field: b0 and k_b as GROMACS writes them."""
    length_nm: float
    k_kJ_mol_nm2: float

    @property
    def length_A(self) -> float:
        return 10.0 * self.length_nm


@dataclass(frozen=True)
class WaterModel:
    """A water model of the force field (pdb2gmx -water NAME, NAME.itp in the folder);
    coordinates: the equilibrated water box `gmx solvate -cs` fills a box with (in the
    GROMACS top folder; spc216.gro serves every 3-site model)."""
    name: str
    residue: str = "SOL"
    atoms: tuple[str, ...] = ("OW", "HW1", "HW2")
    coordinates: str = "spc216.gro"

    @property
    def itp(self) -> str:
        return f"{self.name}.itp"


@dataclass(frozen=True)
class Ion:
    """A monatomic ion of the force field's ions.itp: molecule, residue and atom names."""
    molecule: str
    residue: str
    atom: str
    atomtype: str
    charge_e: float


@dataclass(frozen=True)
class ForceField:
    name: str                                  # pdb2gmx -ff NAME; the folder NAME.ff
    residue_names: dict[str, str]              # base -> residue name in dna.rtp
    renames: dict[str, str]                    # builder (or PDBv3) atom name -> dna.rtp name
    pdb2gmx_options: tuple[str, ...]           # extra options of the ring-closing pdb2gmx call
    terminus_answers: str                      # stdin for pdb2gmx's terminus prompts (see topology.py)
    middle_residues_only: bool                 # a private copy whose dna.r2b maps each residue to its middle form
    o3_p: Bond                                 # the O3'(i)-P(i+1) bond
    angle_c3_o3_p_deg: float                   # C3'-O3'-P
    angle_o3_p_o5_deg: float                   # O3'-P-O5'
    hydrogen_templates: str | None             # dna_models/data file of pdb2gmx's hydrogens, None: not templated
    water_models: dict[str, WaterModel]
    default_water: str
    cation: Ion
    anion: Ion
    phosphate: tuple[str, ...] = ("P", "O1P", "O2P")   # dna.rtp names; [1:] are the non-bridging oxygens
    ions_itp: str = "ions.itp"                 # the folder's file of the ions' moleculetypes

    @property
    def phosphate_oxygens(self) -> tuple[str, ...]:
        """The non-bridging phosphate oxygens (dna.rtp names)."""
        return self.phosphate[1:]

    def rtp_name(self, atom: str) -> str:
        """ATOM (a builder or PDBv3 name) as this force field's dna.rtp spells it."""
        return self.renames.get(atom, atom)

    def water(self, name: str | None = None) -> WaterModel:
        """The water model NAME (default: the force field's recommended one)."""
        key = self.default_water if name is None else name
        if key not in self.water_models:
            raise InputError(f"water model {key!r} is not registered for {self.name}; allowed: "
                             f"{', '.join(self.water_models)}")
        return self.water_models[key]


CHARMM27 = ForceField(
    name="charmm27",
    residue_names=dict(CHARMM_RESNAME),
    # charmm27.ff/dna.arn maps the PDBv3 names itself; the builder writes CHARMM27's
    renames={"OP1": "O1P", "OP2": "O2P", "C7": "C5M"},
    pdb2gmx_options=("-ter",),      # default termini are protein ones; cyclic strands get none
    # should ring closure fail: "None" for charmm27's DNA start (3) and end (5) termini
    terminus_answers="3\n5\n" * 8,
    middle_residues_only=False,
    o3_p=Bond(0.160, 225936.0),     # ffnabonded.itp ON2-P
    angle_c3_o3_p_deg=120.0,        # ffnabonded.itp CN7-ON2-P (as CN9-ON2-P)
    angle_o3_p_o5_deg=104.3,        # ffnabonded.itp ON2-P-ON2
    hydrogen_templates=H_DATA.name,
    water_models={"tip3p": WaterModel("tip3p")},    # watermodels.dat: "recommended"
    default_water="tip3p",
    cation=Ion("NA", "NA", "NA", "SOD", +1.0),      # ions.itp
    anion=Ion("CL", "CL", "CL", "CLA", -1.0),
)

AMBER99SB_ILDN = ForceField(
    name="amber99sb-ildn",
    residue_names=dict(CHARMM_RESNAME),             # dna.rtp: DA DC DG DT (middle forms)
    # amber's rtp calls the thymine methyl carbon C7 and has no arn entry for C5M
    renames={"OP1": "O1P", "OP2": "O2P", "C5M": "C7"},
    pdb2gmx_options=(),
    terminus_answers="3\n5\n" * 8,
    # pdb2gmx would give the first and last residue the 5'/3' forms (DA5 has no phosphate)
    middle_residues_only=True,
    o3_p=Bond(0.161, 192464.0),     # ffbonded.itp OS-P
    angle_c3_o3_p_deg=120.5,        # ffbonded.itp CT-OS-P
    angle_o3_p_o5_deg=102.6,        # ffbonded.itp OS-P-OS
    hydrogen_templates=None,
    water_models={"tip3p": WaterModel("tip3p")},
    default_water="tip3p",
    cation=Ion("NA", "NA", "NA", "Na", +1.0),       # ions.itp
    anion=Ion("CL", "CL", "CL", "Cl", -1.0),
)

REGISTRY: dict[str, ForceField] = {ff.name: ff for ff in (CHARMM27, AMBER99SB_ILDN)}
NAMES: tuple[str, ...] = tuple(REGISTRY)
#: every water model of a registered force field (build-md --solvent offers these and "vacuum")
WATER_MODELS: tuple[str, ...] = tuple(dict.fromkeys(w for ff in REGISTRY.values() for w in ff.water_models))

#: the force field whose names and geometry the builder's nucleotide templates carry
BUILDER = CHARMM27

#: PDB version 3 / 3DNA names -> the builder's (CHARMM27) names; charmm27.ff/dna.arn maps the same way
PDBV3_TO_BUILDER = {"OP1": "O1P", "OP2": "O2P", "C7": "C5M", "H2''": "H2'2"}


def forcefield(name: str) -> ForceField:
    """The registered force field NAME; an InputError naming the allowed ones otherwise."""
    if name not in REGISTRY:
        raise InputError(f"force field {name!r} not supported; allowed: {', '.join(NAMES)}")
    return REGISTRY[name]
