"""The ranking: which part, translational or rotational, dominates each element of D and h."""
