"""The simplified model: its choices, the budget, the guarantee and the torque error."""
