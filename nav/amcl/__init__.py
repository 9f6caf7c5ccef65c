"""Localisation on a saved map: Nav2's AMCL, the original's dormant path made live.

One idea per module: ``config`` (the parameters, Nav2's names where Nav2 has them),
``motion_model`` (Nav2's OmniMotionModel, the seed's choice for a mecanum base),
``likelihood_field`` (the likelihood-field sensor model on the map), ``particle_filter`` (the
filter that strings them together) and ``localisation`` (the filter behind the
``nav.localisation.Localisation`` interface). ``nav.slam: false`` and ``nav.map_file`` select it.
"""
