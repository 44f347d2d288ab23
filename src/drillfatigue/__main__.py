from drillfatigue.cli import run

run()
