"""pytest setup of the motionbus Python package suite: Hypothesis runs derandomized (the same
examples on every run, so CI is stable) with example counts sized for a suite under a minute."""

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "motionbus", derandomize=True, deadline=None, max_examples=int(os.environ.get("MOTIONBUS_HYPOTHESIS_EXAMPLES", "150")),
    suppress_health_check=[HealthCheck.too_slow], database=None)
settings.load_profile("motionbus")
