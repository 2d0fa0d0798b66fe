"""Figures and the HTML report."""

from .page import Page

__all__ = ["Page"]
