"""Re-exports one submodule of the extension module as a package module."""

from __future__ import annotations

from typing import Any, Dict, List


def export(source: Any, namespace: Dict[str, Any]) -> List[str]:
    names = [n for n in dir(source) if not n.startswith("_")]
    for n in names:
        namespace[n] = getattr(source, n)
    return names
