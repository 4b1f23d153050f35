"""The steps of `dnarod compare` that workflows/Snakefile calls, one process each: the
scenes and wave analyses of the rod and the MD (`analyse`), the matched quantities they
record (`matched`), the pre-strained rod (`prestrain`) and the coarse-graining loop
(`cgloop`). The report that reads their files is workflows/report/."""
