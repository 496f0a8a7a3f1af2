"""The library version (one constant in one place)."""

__version__ = "0.1.0"
