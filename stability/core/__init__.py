"""The numerics every problem family shares: the rigid body and its mass properties
(:mod:`~stability.core.body`), quaternions (:mod:`~stability.core.quaternions`), and special
functions: Jacobi and Carlson elliptic functions (:mod:`~stability.core.elliptic`), bracketed
roots (:mod:`~stability.core.roots`), compensated arithmetic
(:mod:`~stability.core.compensated`) and vectorizable sine and cosine
(:mod:`~stability.core.trig`). They import only :mod:`stability.util`.
"""
