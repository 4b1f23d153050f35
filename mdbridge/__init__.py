"""Bridge between the rod and DNA: running the rod and its output files
(`mdbridge.rodrun`), base-pair frames and step parameters (`mdbridge.geometry`),
rod <-> base-pair frames (`mdbridge.rodframes`), all-atom building, GROMACS, MD
analysis."""
