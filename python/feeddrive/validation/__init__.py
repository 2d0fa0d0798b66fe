"""Closed-loop validation: the paper's Secs. 3 and 4 reproduced, and measured runs replayed."""
