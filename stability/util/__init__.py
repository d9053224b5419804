"""Small shared utilities every layer may use: names and units of the Datasets
(:mod:`~stability.util.conventions`), input checks with one-line errors
(:mod:`~stability.util.checks`), thread counts (:mod:`~stability.util.threads`), progress bars
(:mod:`~stability.util.progress`) and the formatting of numbers and sizes
(:mod:`~stability.util.formatting`). They import nothing else of the package.
"""
