"""DNA sequences: validation, complement, random sequences with a seed.

Sequences are strings of A, C, G, T read 5' -> 3' along strand I; input is
case-insensitive and returned upper-case."""
from __future__ import annotations

import numpy as np

from .errors import InputError

ALPHABET = "ACGT"
_COMPLEMENT = str.maketrans("ACGT", "TGCA")


def validate(seq: str, what: str = "sequence") -> str:
    """Upper-case copy of `seq`; InputError naming the first bad letter and its
    1-based position otherwise (allowed: A, C, G, T, any case)."""
    if not isinstance(seq, str):
        raise InputError(f"{what}: expected a string of A, C, G, T, got {type(seq).__name__}")
    s = seq.strip().upper()
    if not s:
        raise InputError(f"{what}: empty (allowed letters A, C, G, T)")
    for k, ch in enumerate(s, start=1):
        if ch not in ALPHABET:
            raise InputError(f"{what}: letter {ch!r} at position {k} is not a DNA base "
                             "(allowed A, C, G, T, case-insensitive)")
    return s


def complement(seq: str) -> str:
    """Base-by-base Watson-Crick complement (A<->T, C<->G), same direction."""
    return validate(seq).translate(_COMPLEMENT)


def reverse_complement(seq: str) -> str:
    """Strand II read 5' -> 3' (the complement, reversed)."""
    return complement(seq)[::-1]


def random_sequence(n: int, seed=None, gc_content: float = 0.5) -> str:
    """Random sequence of n bases from numpy's Generator (default_rng(seed)):
    G and C each with probability gc_content / 2, A and T (1 - gc_content) / 2.
    The same seed gives the same sequence."""
    if int(n) != n or n < 1:
        raise InputError(f"random sequence length must be a positive integer, got {n!r}")
    if not 0.0 <= gc_content <= 1.0:
        raise InputError(f"gc_content must lie in [0, 1], got {gc_content!r}")
    rng = np.random.default_rng(seed)
    p = np.array([1 - gc_content, gc_content, gc_content, 1 - gc_content]) / 2.0
    idx = rng.choice(4, size=int(n), p=p)
    return "".join(ALPHABET[i] for i in idx)
