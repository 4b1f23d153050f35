"""Bridge between the rod and DNA: base-pair frames and step parameters
(`mdbridge.geometry`), rod <-> base-pair frames (`mdbridge.rodframes`),
all-atom building, GROMACS, MD analysis."""
