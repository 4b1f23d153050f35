"""DNA as a rod material: the per-step DNA file (`stepfile`), parameter sets
that make one from a sequence (`parameter_sets`), the exact map from step
parameters to the rod (`steps_to_rod`), the grid material file rodsim reads
(`gridfile`) and the closed, pre-stressed rest state (`closed_rest`).
See docs/dna-rod.md."""
