"""Reproduction of the paper's rod results (Sections 3-6): figures 1-7 and the
quantitative checks of docs/reproduction.md.

One module per figure or check; all of them run real simulations through
`mdbridge.rod.run.run_scene` (the compiled `rodcore` module) or evaluate the
closed-form results of `dnarod.paper.theory` (which calls the C++
`rodcore.analytic` functions). `dnarod paper-figures` drives
them (`dnarod.paper.registry`).
"""
