"""The checkout the sweep tooling is in, and paths inside it named relative to it: a scene in the
repository then has one name in every copy of it (a run's id, a row's scene_file)."""

import os

# This file is CHECKOUT/scripts/rtmsweep/checkout.py.
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def relative(path):
    """PATH relative to the checkout when it is inside it, else PATH as it is."""
    rel = os.path.relpath(path, ROOT)
    return path if rel == os.pardir or rel.startswith(os.pardir + os.sep) else rel
