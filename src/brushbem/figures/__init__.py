"""Figures in one journal style: `figstyle` (sizes, fonts, saving) and `plot` (the figure of one run)."""
