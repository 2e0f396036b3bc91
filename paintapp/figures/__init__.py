"""Figure makers for ``paintapp figures``; each module exposes ``register(subparsers)``."""
