"""What every figure shares: axis labels with units, legends placed clear of the data, the
colours of the axes, and saving as PNG and PDF into an output folder
(:mod:`~stability.plotting.style`). Each family draws its own figures with these.
"""
