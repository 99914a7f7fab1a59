"""A small genetic algorithm that searches the 2W1A's crawling gait, a population at a time.

Each generation's candidates (six arm angles each) go to :func:`sims.runs.evaluate` as one
batch: every candidate is a run of ``crawl_gait.py``, isolated, on local worker processes (or a
Ray cluster with ``--ray``), and the batch comes back in order with each run's ``RESULT``
values. The loop itself is the textbook one the public 2W1A projects write by hand (elitism,
tournament selection, blend crossover, Gaussian mutation), kept small and seeded so the same
command gives the same gaits; DEAP users plug ``evaluate`` in as ``toolbox.map`` instead
(docs/sweeps.md). Written for this project.

Run: python examples/sweeps/ga_crawl.py --population 8 --generations 3
"""

from __future__ import annotations

import argparse
import random
from pathlib import Path

from sims.runs import evaluate, make_executor

SCRIPT = Path(__file__).resolve().parent / "crawl_gait.py"
GENES = (
    "reach_shoulder",
    "reach_elbow",
    "reach_wrist",
    "pull_shoulder",
    "pull_elbow",
    "pull_wrist",
)
LOW, HIGH = 0.0, 300.0  # degrees, the range the course's experiments use


def fitness(record) -> float:
    """Distance crawled; a run that failed scores nothing (and the search goes on)."""
    return float(record.results.get("distance", 0.0)) if record.ok else 0.0


def clip(value: float) -> float:
    return round(min(HIGH, max(LOW, value)), 1)


def child(rng: random.Random, a: dict, b: dict, sigma: float) -> dict:
    out = {}
    for gene in GENES:
        w = rng.random()
        value = w * a[gene] + (1 - w) * b[gene]
        if rng.random() < 0.3:
            value += rng.gauss(0.0, sigma)
        out[gene] = clip(value)
    return out


def search(population: int, generations: int, executor, seed: int = 1, strokes: int = 3):
    """Returns [(generation, best distance, best genes)] and the last scored population."""
    rng = random.Random(seed)
    pop = [{g: clip(rng.uniform(LOW, HIGH)) for g in GENES} for _ in range(population)]
    history = []
    for generation in range(generations):
        batch = [{**genes, "strokes": strokes} for genes in pop]
        records = evaluate(SCRIPT, "2w1a", batch, executor=executor, sweep_seed=seed)
        ranked = zip([fitness(r) for r in records], range(len(pop)), pop, strict=True)
        scored = sorted(ranked, key=lambda t: (-t[0], t[1]))
        best, _, genes = scored[0]
        history.append((generation, best, genes))
        print(f"generation {generation}: best distance {best:.4f} m with {genes}")

        def pick(scored: list = scored) -> dict:
            a, b = rng.sample(scored, 2)
            return a[2] if (a[0], -a[1]) >= (b[0], -b[1]) else b[2]

        elite = [s[2] for s in scored[:2]]
        pop = elite + [child(rng, pick(), pick(), 20.0) for _ in range(population - len(elite))]
    return history, scored


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--population", type=int, default=8)
    parser.add_argument("--generations", type=int, default=3)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workers", type=int, help="local worker processes (default: cores)")
    parser.add_argument("--ray", nargs="?", const="auto", help="a Ray cluster's address")
    args = parser.parse_args()
    chosen = ("ray", args.ray) if args.ray else ("local", None)
    with make_executor(chosen[0], workers=args.workers, address=chosen[1]) as executor:
        search(args.population, args.generations, executor, args.seed)


if __name__ == "__main__":
    main()
