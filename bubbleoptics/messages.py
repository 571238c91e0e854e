"""Error messages: one way to quote a value a user gave without echoing all of it."""

__all__ = ["shorten"]


def shorten(text: str, limit: int = 40) -> str:
    """*text* cut to at most *limit* characters, ``...`` marking the cut (a 400-digit token or a
    long path is not echoed whole into a one-line error).

    >>> shorten("x" * 50)
    'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx...'
    >>> shorten("short")
    'short'
    """
    return text if len(text) <= limit else text[:limit - 3] + "..."
