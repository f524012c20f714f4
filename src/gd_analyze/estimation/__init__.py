"""Identification of an arm's dynamic parameters from recorded torques: preprocessing, the
regressor with drive columns, least squares, and physically consistent standard parameters."""
