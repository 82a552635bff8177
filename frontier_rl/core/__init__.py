"""The exploration engine: pure NumPy and numba, no Gymnasium, no torch.

The sub-packages are the pipeline's stages, each importing only the ones before it
(``make lint`` checks this)::

    world ──▶ sensing ──▶ mapping ──▶ frontiers ─┐
                                 └──▶ navigation ─┴──▶ sim
"""
