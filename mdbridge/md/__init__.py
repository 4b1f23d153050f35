"""The MD layer: an MD build of a rod scene in its stages (`build`, what `dnarod build-md`
does), all-atom duplexes from rod frames (`builder/`), GROMACS (`gromacs/`),
back-mapping rod frames onto atoms (`backmap`), PDB files (`pdbio`) and the one
Watson-Crick pairing check (`integrity`). It imports the rod layer and the ground floor,
never analysis or coarsegrain (docs/architecture.md)."""
