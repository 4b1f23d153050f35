"""Bridge between the rod and DNA, in floors that import only downward
(docs/architecture.md, "The Python layers"): `geometry` and `stats` (ground floor),
`rod` (rod runs, rod <-> base-pair frames, material), `md` (all-atom builder, GROMACS,
back-mapping), then `analysis` and `coarsegrain`."""
