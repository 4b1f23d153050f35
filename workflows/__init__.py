"""The dnarod command line, the Snakemake comparison workflow and reports."""
from dnarod.quiet import quiet_third_party_deprecations

# Before any entry point imports MDAnalysis (workflows/quiet.py says why it must come first).
quiet_third_party_deprecations()
