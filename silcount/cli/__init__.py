"""The ``silcount`` command line: one module per subcommand, dispatched by :data:`silcount.cli.main.COMMANDS`."""
