"""The dispersion study: a free body tossed about its middle axis, uncertain in its moments, the
alignment of its axes, its spin and its start; which uncertainty dominates the flip interval.

:mod:`.measure` draws the members and computes their outputs (closed form, and integrated by
:func:`stability.run_scene`), :mod:`.schema` declares its Dataset, :mod:`.study` is the kind.
"""
