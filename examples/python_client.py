# A gaitforge study from Python, notebook style: each `# %%` is a cell (Jupyter, VS Code,
# or run the whole file: /usr/bin/python3 examples/python_client.py). Needs a build
# (scripts/build.sh: binaries in build/bin, stubs in build/python); docs/python.md.

# %% Import the client from the source tree
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))
from gaitforge_client import Client, InvalidSpec  # noqa: E402

os.makedirs(os.path.join(REPO, "runs"), exist_ok=True)
DB = os.path.join(REPO, "runs", "python-example.db")

# %% A spec as a dict: the fields of docs/spec.md
spec = {
    "name": "rastrigin-from-python",
    "seed": 42,
    "population": 40,
    "generations": 20,
    "objective": {"name": "analytic.rastrigin"},
    "ga": {"elite": 4, "mutation_rate": 0.1},
}


# %% Progress arrives as dicts, once per change (at most every 100 ms)
def show(p):
    best = "-" if p["best"] is None else f"{p['best']:.4f}"
    print(f"\rgeneration {p['generations_done']}/{p['generations_total']}  best {best}", end="")


# %% Run it on a private coordinator with two workers, then read the results
with Client.local(db=DB, workers=2) as gf:
    study_id = gf.submit(spec)                 # or gf.submit("examples/analytic-ga.yaml")
    gf.watch(study_id, on_progress=show)
    print()
    history = gf.history(study_id)             # as_dataframe=True with pandas
    best = gf.hall_of_fame(study_id)[0]
    first = gf.individuals(study_id, generation=0)

    # Errors are exceptions naming the field, never bare gRPC errors
    try:
        gf.submit(dict(spec, population=1))
    except InvalidSpec as e:
        print(f"refused ({e.field}): {e}")

# %% Fitness per generation
for row in history:
    print(f"{row['generation']:3d}  best {row['best']:.4f}  mean {row['mean']:.4f}")
print("best genes:", [round(g, 4) for g in best["genes"]], "fitness", best["fitness"])
print(f"{len(first)} members in generation 0")

# %% With pandas (Debian: python3-pandas) the same tables are DataFrames, e.g.
#     Client("127.0.0.1:50051").history(study_id, as_dataframe=True).plot(x="generation", y="best")
