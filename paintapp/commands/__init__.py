"""Sub-commands of ``paintapp``; each module exposes ``register(subparsers)``."""
