"""Every tolerance of the test suite, in one place, with the reason for its size."""

#: float64 closed forms evaluated two different ways
EXACT = 1e-12
#: reciprocity (acceptance: 1e-12 relative)
RECIPROCITY = 1e-12
#: adaptive quadrature asked for rtol 1e-9..1e-10, compared with closed forms (acceptance 1e-6)
FURNACE = 1e-6
#: independent direction-space quadrature (scipy) vs sample-space cubature
QUADRATURE = 1e-6
#: values re-typed from a paper with 4-6 significant digits
PUBLISHED_5 = 1e-5
#: chi-square significance before the Šidák correction (acceptance: p > 0.01)
CHI2_ALPHA = 0.01
#: Mitsuba 3 computes in float32 (acceptance: 1e-5 relative)
MITSUBA = 1e-5
#: weight = f |cos| / pdf and sample.pdf = pdf(wo, wi) (same formulas, different order of
#: operations); the property test adds the half-vector conditioning term on top
WEIGHT = 1e-9
#: white furnace of the table-based models (acceptance: 1e-3, dielectric R + T 2e-3); the
#: measured figures are in docs/tables.md
FURNACE_TABLE = 1e-3
FURNACE_TABLE_DIELECTRIC = 2e-3
#: reciprocity of the table-based terms (acceptance: 1e-10)
RECIPROCITY_TABLE = 1e-10
#: below the smallest normal float64 a value keeps fewer significant bits (IEEE 754 gradual
#: underflow): relative comparisons measure differences there absolutely (the Beckmann tail
#: reaches it, exp(-e) for e > 708)
SUBNORMAL = 2.2250738585072014e-308
