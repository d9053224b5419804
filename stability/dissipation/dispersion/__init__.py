"""The dispersed Explorer: a long body spun about its minor axis with a spherical damper, uncertain
in its size, mass, spin, damper and start; which uncertainty dominates its time to the flat spin.

:mod:`.measure` draws the members and computes their outputs (by the linear eigenvalue, and
integrated by :func:`stability.dissipation.measure.run_damped`), :mod:`.schema` declares its
Dataset, :mod:`.study` is the kind.
"""
