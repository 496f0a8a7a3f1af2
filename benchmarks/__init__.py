"""Speed measurements of adobe_bsdf (``python -m benchmarks``)."""
