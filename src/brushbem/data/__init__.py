"""Measured tables the library reads at run time (each names the script that measured it)."""
