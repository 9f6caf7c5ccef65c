"""Localisation on a saved map: Nav2's AMCL, the original's dormant path made live.

``particle_filter`` is the filter (Nav2's OmniMotionModel in ``motion_model``, the
likelihood-field sensor model in ``likelihood_field``), ``localisation`` puts it behind the
``Localisation`` interface navigation uses; ``nav.slam: false`` and ``nav.map_file`` select it.
"""
