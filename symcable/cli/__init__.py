"""The ``symcable`` command (:mod:`.main`) and its subcommands."""
