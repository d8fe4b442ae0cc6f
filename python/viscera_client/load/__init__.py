"""The load tester's parts (tools/loadtest.py is its command line): per-session
measurement (stats), the worker processes that stream (worker), the JSON report and its
health checks (report), and the plots (plots, needs matplotlib)."""
