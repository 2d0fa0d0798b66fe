"""The work of each ``feeddrive`` command, one module per command, each with
``main(args) -> exit status``.  :mod:`feeddrive.cli` parses the command line and imports the
module of the command given only when it runs (so ``--help`` imports none of them);
:mod:`.common` holds what the commands share (progress bars, the output-file check)."""
