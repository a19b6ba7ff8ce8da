"""Sub-commands of the ``nfdcal`` CLI. Each module has ``add_parser(subparsers)``; the parser
it adds sets ``run`` (a function ``run(namespace) -> exit code``) as a default. Heavy imports
happen inside ``run`` so ``nfdcal collide`` works without the FE stack."""
