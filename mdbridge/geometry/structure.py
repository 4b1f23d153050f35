"""Base-pair frames of DNA duplexes in anything MDAnalysis reads (PDB, GRO,
TPR + XTC, multi-model PDB), vectorised over trajectory frames.

    bpf = BasePairFrames(universe).run()
    bpf.results.origins   # (T, n_bp, 3)    base-pair origins [A]
    bpf.results.R         # (T, n_bp, 3, 3) base-pair axes (columns x, y, z) in the lab
    bpf.step_parameters() # (T, n_bp - 1, 6) shift, slide, rise [A], tilt, roll, twist [deg]

Recognised residue names: DA DC DG DT, A C G T, AMBER terminal variants
(DA5, DA3, DAN, ...), CHARMM ADE CYT GUA THY. Atom names: C1* or C1', OP1 or O1P.
Only the ring atoms are used (Lu & Olson 2003): base frames by least-squares
fit of the standard base, base-pair frames as 3DNA defines them
(mdbridge.geometry.steps).

Periodic systems: each base's ring atoms are unwrapped about its first ring
atom, and pair and step vectors are minimum images (a ligated duplex under
GROMACS `periodic-molecules` cannot be made whole).
"""
from __future__ import annotations

import warnings

import numpy as np

from dna_models.errors import InputError
from dna_models.nucleotides import PURINES, ring_atom_names, standard_ring_coordinates

from .analysis_base import AnalysisBase, UniverseFrames
from .basefit import fit_frames
from .pbc import minimum_image
from .steps import base_pair_parameters, step_parameters_along

_BASE_OF = {"A": "A", "C": "C", "G": "G", "T": "T",
            "DA": "A", "DC": "C", "DG": "G", "DT": "T",
            "ADE": "A", "CYT": "C", "GUA": "G", "THY": "T"}
_COMPLEMENT = {"A": "T", "T": "A", "G": "C", "C": "G"}
_PAIR_CUTOFF_A = 4.5     # N1(purine)-N3(pyrimidine): ~2.9 A in a Watson-Crick pair, 4.2 A in
                         # the most stretched pair of the 1KX5 nucleosome; stacked neighbours > 5 A
_MIN_BOX_A = 10.0        # smaller "boxes" are PDB placeholders (CRYST1 1 1 1), not cells
_MAX_STEP_A = 10.0       # no base-pair step spans more (rise 3.4 A; a broken chain is refused at 4 A O3'-P)


def base_of_resname(resname: str):
    """A/C/G/T for a DNA residue name, None for anything else.

    Strips AMBER terminal suffixes (DA5, DA3, DAN) and a leading/trailing space."""
    r = str(resname).strip().upper()
    if r in _BASE_OF:
        return _BASE_OF[r]
    if len(r) == 3 and r[:2] in _BASE_OF and r[2] in "53N":
        return _BASE_OF[r[:2]]
    return None


def dna_base(resname: str, where: str) -> str:
    """A/C/G/T for a DNA residue name (base_of_resname), or an InputError naming WHERE."""
    b = base_of_resname(resname)
    if b is None:
        raise InputError(f"{where}: residue {str(resname).strip()} is not a DNA nucleotide (allowed: DA DC DG DT, "
                         "their AMBER terminal forms DA5 DA3 ..., A C G T, ADE CYT GUA THY)")
    return b


def _canonical_atom_name(name: str) -> str:
    n = str(name).strip().replace("*", "'")
    return {"OP1": "O1P", "OP2": "O2P", "C7": "C5M"}.get(n, n)


def residue_label(res) -> str:
    seg = getattr(res, "segid", "") or ""
    try:
        chain = res.atoms[0].chainID
    except Exception:  # noqa: BLE001 - topologies without chain IDs
        chain = ""
    where = chain or seg
    return f"{res.resname}{res.resid}" + (f" (chain {where})" if where else "")


def _ring_indices(res, base):
    names = [_canonical_atom_name(n) for n in res.atoms.names]
    idx = []
    for a in ring_atom_names(base):
        if a not in names:
            raise InputError(
                f"residue {residue_label(res)}: ring atom {a} missing (needed to fit the "
                f"standard {base} base; ring atoms {', '.join(ring_atom_names(base))}; "
                f"present: {', '.join(names)})")
        idx.append(res.atoms[names.index(a)].index)
    return idx


def _box(dimensions):
    if dimensions is None:
        return None
    d = np.asarray(dimensions, dtype=float)
    if d.shape[-1] != 6 or np.any(d[..., :3] < _MIN_BOX_A):
        return None
    return d


def _is_empty(path) -> bool:
    """Nothing but white space (MDAnalysis would say "Compressed file ended ..." or worse)."""
    with open(path, "rb") as f:
        head = f.read(4096)
    return not head.strip() and len(head) < 4096


def load_universe(structure, *trajectories):
    """MDAnalysis Universe of STRUCTURE (+ TRAJECTORIES, concatenated) for the commands:
    an InputError naming the file for a missing or unreadable one, with the first line
    of MDAnalysis's reason and the formats to use."""
    from pathlib import Path

    import MDAnalysis
    files = [str(structure)] + [str(t) for t in trajectories]
    for f in files:
        if Path(f).is_dir():
            raise InputError(f"{f}: a folder; give the structure and trajectory files in it "
                             f"(e.g. {Path(f) / 'md.tpr'} {Path(f) / 'md.xtc'})")
        if not Path(f).is_file():
            raise InputError(f"{f}: file not found")
        if _is_empty(Path(f)):
            raise InputError(f"{f}: the file is empty (no atoms, no frames)")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return MDAnalysis.Universe(*files)
    except Exception as e:  # noqa: BLE001 - MDAnalysis raises many types for bad files
        why = (str(e).strip().splitlines() or [""])[0]
        raise InputError(f"{' + '.join(files)}: MDAnalysis cannot read it ({type(e).__name__}: {why}); "
                         "give a structure (PDB, GRO, TPR, ...) and trajectories (XTC, TRR, DCD, "
                         "multi-model PDB, ...) with their usual extensions") from None


def read_pairs_file(path):
    """Pairs from a 3DNA bpfile (`find_pair` output) or a plain two-column file.

    Returns (pairs, numbering): 3DNA bpfiles number nucleotides 1, 2, ... in file
    order ("serial"); a plain file of lines "resid_I resid_II" (``#`` comments)
    gives residue ids ("resid")."""
    from pathlib import Path
    p = Path(path)
    try:
        lines = p.read_text().splitlines()
    except OSError as e:
        raise InputError(f"{path}: cannot read pairs file ({e.strerror})") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a pairs file (its bytes are binary; a 3DNA bpfile or lines "
                         "'resid_I resid_II' expected)") from None
    is_bpfile = any("# number of base-pairs" in ln for ln in lines[:6])
    pairs = []
    body = lines[5:] if is_bpfile else lines
    for k, ln in enumerate(body, start=6 if is_bpfile else 1):
        s = ln.split("#")[0].split()
        if not s:
            continue
        if is_bpfile and s[0].startswith("#"):
            continue
        try:
            pairs.append((int(s[0]), int(s[1])))
        except (ValueError, IndexError):
            raise InputError(f"{path}, line {k}: expected two residue numbers, got {ln.strip()!r}") from None
    if not pairs:
        raise InputError(f"{path}: no base pairs found (expected lines 'resid_I resid_II' "
                         "or a 3DNA bpfile from find_pair)")
    return pairs, ("serial" if is_bpfile else "resid")


class BasePairFrames(AnalysisBase):
    """Base and base-pair frames of a DNA duplex along a trajectory: an analysis of the one
    loop (mdbridge/geometry/analysis_base.py), run(start, stop, step, frames, progress).

    universe: an MDAnalysis Universe. pairs: None (found automatically: two
    strands (segments/chains, or backbone breaks), antiparallel, complementary,
    paired by N1/N3 distance; one strand: a hairpin paired with itself) or a list
    of (residue I, residue II) numbers, strand I first, in the numbering
    `pair_numbering` = "resid" (residue ids, must be unique among nucleotides) or
    "serial" (1-based nucleotide order in the file, as in 3DNA bpfiles).
    pbc: use the box for minimum images (ignored when the file has no box).
    """

    def __init__(self, universe, pairs=None, pair_numbering="resid", pbc=True, verbose=False):
        super().__init__(UniverseFrames(universe), verbose)
        self.universe = universe
        self.pbc = pbc
        nts = [(r, base_of_resname(r.resname)) for r in universe.residues]
        nts = [(r, b) for r, b in nts if b is not None]
        if not nts:
            raise InputError("no DNA nucleotides found (residue names allowed: DA DC DG DT, "
                             "A C G T, DA5/DA3 variants, ADE CYT GUA THY)")
        self._nts = nts
        if pairs is None:
            pair_idx = self._auto_pairs()
        else:
            pair_idx = self._explicit_pairs(pairs, pair_numbering)
        self._check_pairs(pair_idx)
        self.pair_index = pair_idx                        # [(i, j)] into self._nts
        self.pairs = [(nts[i][0], nts[j][0]) for i, j in pair_idx]
        self.sequence = "".join(nts[i][1] for i, _ in pair_idx)
        self.n_bp = len(pair_idx)
        self._prepare_atoms()

    # -- pairing ---------------------------------------------------------
    def _explicit_pairs(self, pairs, numbering):
        if numbering == "serial":
            key = {k + 1: k for k in range(len(self._nts))}
        elif numbering == "resid":
            key = {}
            for k, (r, _) in enumerate(self._nts):
                if r.resid in key:
                    raise InputError(
                        f"residue id {r.resid} occurs twice among the nucleotides "
                        f"({residue_label(self._nts[key[r.resid]][0])}, {residue_label(r)}): "
                        "give pairs as 1-based nucleotide serial numbers instead")
                key[r.resid] = k
        else:
            raise InputError(f"pair_numbering must be 'resid' or 'serial', not {numbering!r}")
        out = []
        for a, b in pairs:
            for x in (a, b):
                if x not in key:
                    raise InputError(f"base pair ({a}, {b}): no nucleotide with {numbering} {x}")
            out.append((key[a], key[b]))
        return out

    def _check_pairs(self, pair_idx):
        """Pairs must join two different nucleotides, each nucleotide may be in one
        pair only, a pair that is not Watson-Crick is flagged, and consecutive
        pairs must be consecutive along strand I's backbone: a missing nucleotide
        would otherwise merge two steps into one without a word."""
        label = lambda k: residue_label(self._nts[k][0])  # noqa: E731
        used = {}
        for i, j in pair_idx:
            if i == j:
                raise InputError(f"base pair ({label(i)}, {label(j)}): a nucleotide cannot pair with itself")
            for x in (i, j):
                if x in used:
                    raise InputError(f"nucleotide {label(x)} is in two base pairs, ({label(used[x][0])}, "
                                     f"{label(used[x][1])}) and ({label(i)}, {label(j)}); each may pair once")
                used[x] = (i, j)
            if _COMPLEMENT[self._nts[i][1]] != self._nts[j][1]:
                warnings.warn(f"base pair ({label(i)}, {label(j)}) is not Watson-Crick "
                              f"({self._nts[i][1]}-{self._nts[j][1]})", stacklevel=3)
        box = _box(self.universe.dimensions) if self.pbc else None
        for (i, _), (k, _) in zip(pair_idx, pair_idx[1:]):
            o3 = [a for a in self._nts[i][0].atoms if _canonical_atom_name(a.name) == "O3'"]
            p = [a for a in self._nts[k][0].atoms if _canonical_atom_name(a.name) == "P"]
            if not (o3 and p):
                continue  # no backbone atoms: nothing to check
            d = float(np.linalg.norm(minimum_image(p[0].position - o3[0].position, box)))
            # bonded 1.6 A; rebuilt models (3DNA, mdbridge.md.builder) stretch it to ~2.6 A;
            # a missing nucleotide leaves >= 5 A
            if d > 4.0:
                raise InputError(f"broken chain: {label(i)} O3' and {label(k)} P are {d:.2f} A apart "
                                 "(bonded: 1.6 A), yet they are consecutive base pairs on strand I; "
                                 "a nucleotide is missing or the structure is damaged (or the explicit "
                                 "pairs skip one, or are not in strand-I order)")

    def _strands(self):
        """Nucleotide index lists, one per strand, in file order."""
        res = [r for r, _ in self._nts]
        for attr in ("segids", "chainIDs"):
            try:
                labels = [getattr(r.atoms, attr)[0] for r in res]
            except (AttributeError, Exception):  # noqa: BLE001 - attribute absent
                continue
            if len(set(labels)) > 1:
                strands, cur = [], [0]
                for k in range(1, len(res)):
                    if labels[k] != labels[k - 1]:
                        strands.append(cur)
                        cur = []
                    cur.append(k)
                strands.append(cur)
                return strands
        # one segment: split where the backbone O3'(k) - P(k+1) link is broken
        box = _box(self.universe.dimensions) if self.pbc else None
        strands, cur = [], [0]
        for k in range(1, len(res)):
            o3 = [a for a in res[k - 1].atoms if _canonical_atom_name(a.name) == "O3'"]
            p = [a for a in res[k].atoms if _canonical_atom_name(a.name) == "P"]
            linked = False
            if o3 and p:
                v = minimum_image(p[0].position - o3[0].position, box)
                linked = np.linalg.norm(v) < 2.5
            if not linked:
                strands.append(cur)
                cur = []
            cur.append(k)
        strands.append(cur)
        return strands

    def _auto_pairs(self):
        strands = self._strands()
        n1n3 = []
        for r, b in self._nts:
            want = "N1" if b in PURINES else "N3"
            a = [x for x in r.atoms if _canonical_atom_name(x.name) == want]
            if not a:
                raise InputError(f"residue {residue_label(r)}: atom {want} missing "
                                 "(needed to find its pairing partner)")
            n1n3.append(a[0].position)
        X = np.array(n1n3, dtype=float)
        box = _box(self.universe.dimensions) if self.pbc else None
        if len(strands) == 2:
            I, II = strands
        elif len(strands) == 1:
            I = II = strands[0]
        else:
            raise InputError(
                f"found {len(strands)} DNA strands "
                f"({', '.join(residue_label(self._nts[s[0]][0]) + '..' for s in strands)}): "
                "automatic pairing handles one duplex (two strands, or one hairpin); "
                "pass the pairs explicitly (--pairs FILE)")
        d = np.linalg.norm(minimum_image(X[I][:, None, :] - X[II][None, :, :], box), axis=-1)
        comp = np.array([[_COMPLEMENT[self._nts[i][1]] == self._nts[j][1] for j in II] for i in I])
        d = np.where(comp, d, np.inf)
        if I is II:  # hairpin: a base cannot pair with itself or its neighbours
            k = np.arange(len(I))
            d[np.abs(k[:, None] - k[None, :]) < 3] = np.inf
        best_j = np.argmin(d, axis=1)
        best_i = np.argmin(d, axis=0)
        pairs = [(I[a], II[best_j[a]]) for a in range(len(I))
                 if d[a, best_j[a]] < _PAIR_CUTOFF_A and best_i[best_j[a]] == a]
        if I is II:
            pairs = [(i, j) for i, j in pairs if i < j]
        if not pairs:
            raise InputError(
                "no Watson-Crick base pairs found between strand I "
                f"({residue_label(self._nts[I[0]][0])}..{residue_label(self._nts[I[-1]][0])}) and strand II "
                f"({residue_label(self._nts[II[0]][0])}..{residue_label(self._nts[II[-1]][0])}): "
                f"no complementary N1/N3 pair closer than {_PAIR_CUTOFF_A} A; unpaired strands "
                "(pass the pairs explicitly with --pairs FILE if the duplex is distorted)")
        js = [j for _, j in pairs]
        if any(b >= a for a, b in zip(js, js[1:])):
            raise InputError("base pairs found are not antiparallel (strand II residues do not run "
                             "backwards along strand I): pass the pairs explicitly")
        i_first = I.index(pairs[0][0])
        i_last = I.index(pairs[-1][0])
        inner = I[i_first:i_last + 1]
        missing = [i for i in inner if i not in {p[0] for p in pairs}]
        if missing:
            raise InputError("unpaired bases inside the duplex: "
                             + ", ".join(residue_label(self._nts[i][0]) for i in missing)
                             + " (no complementary partner within "
                             f"{_PAIR_CUTOFF_A} A by N1/N3 distance); pass the pairs explicitly")
        ends = [i for i in I if i not in inner and (I is not II or i < pairs[-1][1])]
        if ends and I is not II:
            warnings.warn("unpaired overhang nucleotides ignored: "
                          + ", ".join(residue_label(self._nts[i][0]) for i in ends), stacklevel=3)
        return pairs

    # -- atoms -------------------------------------------------------------
    def _prepare_atoms(self):
        """Ring-atom index arrays, grouped by ring size (purines 9, pyrimidines 6)."""
        groups = {}
        for col, (i, j) in enumerate(self.pair_index):
            for strand, k in ((0, i), (1, j)):
                r, b = self._nts[k]
                idx = _ring_indices(r, b)
                g = groups.setdefault(len(idx), {"atoms": [], "std": [], "slot": []})
                g["atoms"].append(idx)
                g["std"].append(standard_ring_coordinates(b))
                g["slot"].append((strand, col))
        self._groups = []
        all_idx = []
        offset = 0
        for n, g in sorted(groups.items()):
            a = np.array(g["atoms"], dtype=int)
            self._groups.append((offset, a.shape, np.array(g["std"]), np.array(g["slot"], dtype=int)))
            all_idx.append(a.ravel())
            offset += a.size
        self._atom_index = np.concatenate(all_idx)
        self._atoms = self.universe.atoms[self._atom_index]

    # -- analysis ------------------------------------------------------------
    def frames_from_positions(self, positions, box=None):
        """Frames from ring-atom positions (T, n_atoms, 3) in the order of
        self._atom_index (vectorised over T). Returns a dict of arrays."""
        pos = np.asarray(positions, dtype=float)
        T = pos.shape[0]
        box = _box(box) if (self.pbc and box is not None) else None
        bb = None if box is None else box[:, None, None, :]
        R_base = np.empty((T, 2, self.n_bp, 3, 3))
        o_base = np.empty((T, 2, self.n_bp, 3))
        rmsd = np.empty((T, 2, self.n_bp))
        for start, shape, std, slot in self._groups:
            n_res, n_ring = shape
            X = pos[:, start:start + n_res * n_ring, :].reshape(T, n_res, n_ring, 3)
            if bb is not None:  # unwrap each base about its first ring atom
                X = X[:, :, :1, :] + minimum_image(X - X[:, :, :1, :], bb)
            R, o, rms = fit_frames(std[None], X)
            R_base[:, slot[:, 0], slot[:, 1]] = R
            o_base[:, slot[:, 0], slot[:, 1]] = o
            rmsd[:, slot[:, 0], slot[:, 1]] = rms
        o_I, o_II = o_base[:, 0], o_base[:, 1]
        if box is not None:
            o_II = o_I + minimum_image(o_II - o_I, box[:, None, :])
        bp, R, o = base_pair_parameters(R_base[:, 0], o_I, R_base[:, 1], o_II)
        return {"R": R, "origins": o, "bp_parameters": bp, "R_base": R_base,
                "o_base": np.stack([o_I, o_II], axis=1), "rmsd": rmsd}

    # -- the loop's steps (mdbridge/geometry/analysis_base.py) ----------------
    # Positions are read one frame at a time and fitted CHUNK_FRAMES frames at once:
    # vectorised numpy, with the memory of one chunk (a 158-bp duplex: ~60 MB).
    CHUNK_FRAMES = 2000

    def _prepare(self):
        self._parts, self._pos, self._boxes, self._all_boxes = [], [], [], []

    def _single_frame(self):
        self._pos.append(self._atoms.positions.astype(float))
        box = self.universe.dimensions
        box = None if box is None else np.array(box, dtype=float)
        self._boxes.append(box)
        self._all_boxes.append(box)
        if len(self._pos) >= self.CHUNK_FRAMES:
            self._fit_chunk()

    def _fit_chunk(self):
        if self._pos:
            b = np.array(self._boxes) if all(x is not None for x in self._boxes) else None
            self._parts.append(self.frames_from_positions(np.array(self._pos), b))
            self._pos.clear()
            self._boxes.clear()

    def _conclude(self):
        """results: origins, R, bp_parameters, R_base (T, 2, n_bp, 3, 3) with strand II's
        base frames as fitted, o_base, rmsd, box (T, 6) or None, time [ps], frame."""
        self._fit_chunk()
        res = self.results
        res.update({k: np.concatenate([p[k] for p in self._parts]) for k in self._parts[0]})
        res.time = np.array(self.times_ps)
        res.frame = np.array(self.frames)
        res.box = None
        if self.pbc and all(b is not None for b in self._all_boxes):
            b = np.array(self._all_boxes)
            res.box = b if _box(b) is not None else None
        del self._parts, self._pos, self._boxes, self._all_boxes

    def step_parameters(self, periodic=False):
        """(T, n_bp - 1, 6) step parameters (shift, slide, rise [A], tilt, roll,
        twist [deg]); periodic=True appends the closing step n_bp -> 1 (T, n_bp, 6).
        Step translations are minimum images when the trajectory has a box."""
        r = self.results
        box = r.box if self.pbc else None
        if periodic and box is None:
            self._check_closing_step_without_box()
        return step_parameters_along(r.R, r.origins, box=box, periodic=periodic)

    def _check_closing_step_without_box(self):
        """Without a box the closing step is taken as it lies in space: right for a
        ring closed in space (a minicircle), silently off by the period for a
        periodic duplex whose box the file does not carry."""
        o = np.asarray(self.results.origins)
        span = float(np.linalg.norm(o[:, 0] - o[:, -1], axis=-1).max())
        if span > _MAX_STEP_A:
            why = ("the box is ignored (pbc off, --no-pbc)" if not self.pbc else
                   "the structure carries no periodic box (no CRYST1 record in a PDB, or one "
                   f"under {_MIN_BOX_A:g} A)")
            raise InputError(
                f"the closing step (base pair {self.n_bp} -> 1) spans {span:.2f} A, more than any "
                f"base-pair step ({_MAX_STEP_A:g} A): the duplex is periodic and {why}. Give the box: "
                "a CRYST1 record (dnarod build-dna --periodic writes one), a GRO or TPR that has it, "
                "or `dnarod helical-params ... --box LX LY LZ`; a ring closed in space needs none")
