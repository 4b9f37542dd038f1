"""The tool's one error with an exit status of its own."""


class InputError(Exception):
    """A bad input: message and exit status (2 arguments, 3 scene)."""

    def __init__(self, message, code):
        super().__init__(message)
        self.code = code
