"""Growth measured per member from its tangents: finite-time Lyapunov exponents.

- :mod:`.ftle`: :func:`run_tangents`, members of a scene carried with their tangent vectors
  (:func:`stability.engine.tangent.tangent_scene`) through the one pipeline
  (:func:`stability.ensemble.chunks.run_plan`), renormalised at fixed intervals, and what that
  measures: the FTLE over the run and over each window, its running history, the instantaneous
  rate of the leading tangent, the finite-time spectrum and the largest singular value of the
  state-transition matrix;
- :mod:`.schema`: the Dataset it returns, declared in the register.
"""
