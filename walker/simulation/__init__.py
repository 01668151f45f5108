"""Simulation: the integrator's Python side, runs, stride maps and terrain."""
