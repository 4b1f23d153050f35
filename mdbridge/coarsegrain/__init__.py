"""Coarse-graining of all-atom DNA into the rod (docs/coarse-graining.md).

    from mdbridge.coarsegrain import StepEnsemble, CoarseGrain
    cg = CoarseGrain(StepEnsemble(q, sequence), temperature_K=300.0).run()

`from_trajectory` reads any duplex trajectory MDAnalysis reads (through
mdbridge.geometry.BasePairFrames); `write_params` writes params.json.
"""
from .ensemble import StepEnsemble
from .estimator import CoarseGrain, default_m_values

__all__ = ["StepEnsemble", "CoarseGrain", "default_m_values"]
