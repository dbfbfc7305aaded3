# CLI tests are added in this file (see run_cli.cmake for what each checks).
