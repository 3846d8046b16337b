"""Importance-based monitoring of a spreading fire's perimeter (on-board fire map, rate of spread, cell importance, planning windows) and a circling baseline."""
