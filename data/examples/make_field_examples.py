"""Regenerate the synthetic field-unit examples in ``field/`` (see README.md here).

    python data/examples/make_field_examples.py

The files come from :func:`drillfatigue.io.examples.write_field_examples`:
a 24 h rig day (drilling with connections, off-bottom circulation, a wiper
trip) as LAS 2.0, WITSML 1.4.1.1 log XML and CSV; the drilling part as a
depth-indexed LAS; a J-well survey in ft as CSV and WITSML trajectory; a
string tally in field units.
"""

from pathlib import Path

from drillfatigue.io.examples import write_field_examples

if __name__ == "__main__":
    for path in write_field_examples(Path(__file__).with_name("field")):
        print(f"wrote {path}")
