"""Ideal B-DNA geometry.

Arnott fibre B-DNA (Chandrasekaran & Arnott 1989, Landolt-Bornstein VII/1b;
Arnott & Hukins 1972 BBRC 47:1504), as built by 3DNA `fiber` (model 4): a
perfect helix of 10 base pairs per turn, i.e. helical twist 36 degrees, pitch 33.75 A, so
helical rise 3.375 Angstrom per base pair (quoted as 3.38 A; 3DNA's fibre
coordinates give 3.375 +- 1e-3, tests/python/test_geometry_3dna.py). In the 3DNA (Olson 2001) base-pair
frame the fibre's local step parameters vary slightly with sequence (slide
~0.4-0.5 A, roll ~1.7 deg, twist 33.9-38.0 deg; refdata/fiber_bdna/bp_step.par)
because the fibre's helix axis does not pass through the base-pair origins.

The idealised duplex used for building (3DNA's rebuild example
`ideal_B_36_3.38.par`) has step parameters (0, 0, 3.38 A, 0, 0, 36 deg) and
zero base-pair parameters: STEP_PARAMETERS below.
"""
from .units import Units

FIBRE_RISE_A = 3.375   # Arnott fibre B-DNA helical rise [Angstrom] (pitch 33.75 A / 10)
# the rounded rise per base pair of ideal duplexes and of the rod (3.38 A) [Angstrom]: its one
# source is dna_models/data/dna_elastic_constants.toml ([b_dna] rise_A), read by units.py
RISE_A = Units.paper().rise_A
TWIST_DEG = 36.0       # helical twist per base pair [degrees] (10 bp per turn)

#: step parameters (shift, slide, rise [A], tilt, roll, twist [deg]) of ideal B-DNA
STEP_PARAMETERS = (0.0, 0.0, RISE_A, 0.0, 0.0, TWIST_DEG)
