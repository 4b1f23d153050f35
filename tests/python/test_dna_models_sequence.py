"""dna_models.sequence: validation messages, complement rules, seeded randomness."""
import numpy as np
import pytest

from dna_models.errors import InputError
from dna_models.sequence import complement, random_sequence, reverse_complement, validate


def test_validate_is_case_insensitive():
    assert validate("acGt") == "ACGT"


def test_validate_names_bad_letter_and_position():
    with pytest.raises(InputError, match=r"'U' at position 3.*allowed A, C, G, T"):
        validate("ACUG")


def test_complement_watson_crick():
    assert complement("AACGT") == "TTGCA"
    # the Dickerson dodecamer is self-complementary (its reverse complement is itself)
    assert reverse_complement("CGCGAATTCGCG") == "CGCGAATTCGCG"


def test_random_sequence_seeded_and_composition():
    a = random_sequence(20000, seed=7, gc_content=0.3)
    assert a == random_sequence(20000, seed=7, gc_content=0.3)
    assert a != random_sequence(20000, seed=8, gc_content=0.3)
    counts = np.array([a.count(b) for b in "ACGT"]) / len(a)
    # binomial standard error ~0.003: 5 sigma
    assert np.allclose(counts, [0.35, 0.15, 0.15, 0.35], atol=0.015)
    validate(a)


def test_random_sequence_rejects_bad_length():
    with pytest.raises(InputError, match="positive integer"):
        random_sequence(0)
