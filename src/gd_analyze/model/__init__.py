"""The robot model: links, joints, drives, mounting, limits, and its loaders (TOML, URDF, Pinocchio)."""
