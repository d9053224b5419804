"""The stability map: measured against analytic Omega^2 for every shape of body and every axis.

- :mod:`.shapes`: the triangle of allowed moments, its edges, and run lengths over it;
- :mod:`.measure`: the map's runs and its Dataset;
- :mod:`.ftle_map`: the map from tangents, the FTLE of each shape beside the analytic rate;
- :mod:`.study`: the study kind ``stability_map``;
- :mod:`.figures`: its figures.
"""
