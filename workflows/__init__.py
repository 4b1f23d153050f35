"""The dnarod command line, the Snakemake comparison workflow and reports."""
