"""`python -m dnarod.steps SUBCOMMAND ...`: the wave-analysis steps of workflows/Snakefile
(workflows/steps/analyse.py: scene, rod, md, modulus, prestrain-scene)."""
import sys

from dnarod.steps.analyse import main

sys.exit(main())
