"""Generated kernels: do not edit; see scripts/generate_kernels.py."""
