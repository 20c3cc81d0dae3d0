"""Symbolic derivation of the wobbling-disk ultrasonic motor model (build time only)."""
GENERATOR_VERSION = "2.1.0"
