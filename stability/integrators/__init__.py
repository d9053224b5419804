"""The methods on Euler's equations, one module per method family: their step kernels and
:class:`~stability.integrators.spec.MethodSpec` (:mod:`.spec`), and the kernels the families'
own methods are built from (:mod:`.rotations`, the composition tables of :mod:`.composition`).

The table of the free body's methods by name is :data:`stability.free_body.methods.METHODS`
(``stability.METHODS``), which adds the free body's exact flow; each other family lists its own
in its ``methods.py``.
"""
