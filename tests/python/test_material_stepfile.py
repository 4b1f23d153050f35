"""The per-step DNA file: round trip and every kind of bad input."""
import h5py
import numpy as np
import pytest

from dna_models.errors import InputError
from mdbridge.rod.material.parameter_sets import olson1998_steps, paper_steps, step_material
from mdbridge.rod.material.stepfile import StepMaterial, read_steps, write_steps


def _sm():
    sm = olson1998_steps("ACGTTGCAAGT", closed=True)
    sm.step_params_err = np.full_like(sm.step_params, 0.01)
    return sm


def test_round_trip(tmp_path):
    sm = _sm()
    write_steps(tmp_path / "s.h5", sm)
    back = read_steps(tmp_path / "s.h5")
    assert back.sequence == sm.sequence and back.closed is True and back.source == sm.source
    for name in ("step_params", "stiffness", "mass", "inertia", "step_params_err"):
        assert np.array_equal(getattr(back, name), getattr(sm, name)), name
    assert back.stiffness_err is None and back.temperature_K == sm.temperature_K
    assert h5py.File(tmp_path / "s.h5")["step_params"].shape == (11, 6)
    # and as a parameter set
    assert step_material(sm.sequence, str(tmp_path / "s.h5")).sequence == sm.sequence
    with pytest.raises(InputError, match="differs from the given one"):
        step_material("ACGTTGCAAGA", str(tmp_path / "s.h5"))


def test_open_has_one_step_fewer():
    assert paper_steps("ACGTA", closed=False).step_params.shape == (4, 6)
    assert paper_steps("ACGTA", closed=True).step_params.shape == (5, 6)


def _write_bad(tmp_path, **changes):
    sm = _sm()
    write_steps(tmp_path / "b.h5", sm)
    with h5py.File(tmp_path / "b.h5", "a") as f:
        for k, v in changes.items():
            if k == "format":
                f.attrs["format"] = v
                continue
            del f[k]
            if v is not None:
                f[k] = v
    return tmp_path / "b.h5"


@pytest.mark.parametrize("change, message", [
    (dict(format="dnarod-steps/0"), "attribute 'format'"),
    (dict(stiffness=None), "dataset 'stiffness' missing"),
    (dict(step_params=np.zeros((10, 6))), "dataset 'step_params' has shape 10 x 6, expected 11 x 6"),
    (dict(sequence="ACGTTGCAAGU"), "letter 'U' at position 11"),
    (dict(mass=-np.ones(11)), "dataset 'mass'"),
])
def test_bad_files(tmp_path, change, message):
    p = _write_bad(tmp_path, **change)
    with pytest.raises(InputError, match=message) as e:
        read_steps(p)
    assert str(p) in str(e.value)


def test_bad_stiffness(tmp_path):
    sm = _sm()
    F = sm.stiffness.copy()
    F[3, 0, 1] += 0.5
    p = _write_bad(tmp_path, stiffness=F)
    with pytest.raises(InputError, match=r"'stiffness' is not symmetric at index 3"):
        read_steps(p)
    F = sm.stiffness.copy()
    F[5] = -F[5]
    with pytest.raises(InputError, match=r"'stiffness' is not positive definite at index 5"):
        read_steps(_write_bad(tmp_path, stiffness=F))
    F = sm.stiffness.copy()
    F[2, 4, 4] = np.nan
    with pytest.raises(InputError, match=r"'stiffness' has a non-finite value \(nan\) at index \[2, 4, 4\]"):
        read_steps(_write_bad(tmp_path, stiffness=F))
    I = sm.inertia.copy()
    I[0, 2, 2] = -1.0
    with pytest.raises(InputError, match=r"'inertia' is not positive definite at index 0"):
        read_steps(_write_bad(tmp_path, inertia=I))


def test_not_hdf5(tmp_path):
    (tmp_path / "x.h5").write_text("no")
    with pytest.raises(InputError, match="cannot open as HDF5"):
        read_steps(tmp_path / "x.h5")


def test_validate_in_memory():
    sm = _sm()
    bad = StepMaterial(**{**sm.__dict__, "closed": False})      # 11 steps for an open 11-bp duplex
    with pytest.raises(InputError, match="expected 10 x 6"):
        bad.validate()


def test_atomic_mass_from_chemical_formulas():
    """mass = "atoms": the A-T and G-C pairs weigh what the CHARMM27 residue formulas
    say (DA C10H11N5O5P, DT C10H12N2O7P, DG C10H11N5O6P, DC C9H11N3O6P: chain
    residues with their 5' phosphate), and the inertia is positive definite."""
    from mdbridge.rod.material.parameter_sets import atomic_mass_inertia
    w = {"C": 12.011, "H": 1.008, "N": 14.007, "O": 15.999, "P": 30.974}

    def f(C, H, N, O):
        return C * w["C"] + H * w["H"] + N * w["N"] + O * w["O"] + w["P"]
    m, I = atomic_mass_inertia("ATGC")
    at, gc = f(10, 11, 5, 5) + f(10, 12, 2, 7), f(10, 11, 5, 6) + f(9, 11, 3, 6)
    assert m == pytest.approx([at, at, gc, gc], abs=1e-9)
    assert np.linalg.eigvalsh(I)[:, 0].min() > 0
    # polar moment about the helix axis within 15 % of the paper's I3 = 2 I h
    from mdbridge.rod.material.parameter_sets import paper_mass_inertia
    assert I[0, 2, 2] == pytest.approx(paper_mass_inertia(1)[1][0, 2, 2], rel=0.15)
