"""All-atom DNA duplexes from base-pair frames (3DNA rebuild's method) and
their chemistry checks. Public entry points: `mdbridge.build`."""
