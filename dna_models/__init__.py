"""DNA facts as data: units and elastic constants (Sec 2.1-2.2), bases,
nucleotide templates, B-DNA geometry, sequences."""
