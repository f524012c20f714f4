"""The proofs over a joint-limit region: enclosures rounded outward, the bound of every pair, D_s positive definite."""
