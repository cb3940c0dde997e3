"""Ensembles on one machine or a cluster.

An ensemble (``scene.ensemble(...)``) draws each run's inputs from its seed and the
run's index alone, so any range of runs gives the rows a plain loop gives. The backends
here only decide where the ranges run:

* ``"rayon"`` (default): every core of this machine, in Rust, the GIL released;
* ``"loop"``: one run at a time in a Python loop (the reference the others must equal);
* ``"dask"``: chunks of runs as tasks on a Dask cluster (``dask.distributed``), each
  task a range integrated on one worker thread; the chunks' tables come back and are
  joined in run order;
* ``"ray"``: the same chunks as Ray tasks (after ``ray.init(...)``).

Every backend returns a :class:`Table`. Failed runs stay in it, with NaN outputs and
their error's kind and message.
"""

import numpy as np

__all__ = ["Table", "run"]


class Table:
    """The rows of an ensemble: NumPy columns by name (``run``, the inputs, the outputs,
    ``error_kind``, ``error``), one row per run in run order."""

    def __init__(self, columns):
        self.columns = dict(columns)

    @classmethod
    def concat(cls, tables):
        tables = list(tables)
        names = list(tables[0].columns)
        return cls({k: np.concatenate([t.columns[k] for t in tables]) for k in names})

    def __getitem__(self, name):
        return self.columns[name]

    def __len__(self):
        return len(self.columns["run"])

    @property
    def names(self):
        return list(self.columns)

    @property
    def failed(self):
        """A boolean mask of the runs that failed."""
        return self.columns["error_kind"] != ""

    def equals(self, other):
        """Same columns, same values bit for bit (NaN included)."""
        if self.names != other.names:
            return False
        for k in self.names:
            a, b = self.columns[k], other.columns[k]
            if a.dtype.kind == "f":
                if a.shape != b.shape or a.view(np.uint64).tolist() != b.view(np.uint64).tolist():
                    return False
            elif not np.array_equal(a, b):
                return False
        return True

    def save(self, path):
        """Writes the table to ``path`` as NumPy ``.npz`` (no pickle needed to read it)."""
        np.savez(path, **self.columns)

    @classmethod
    def load(cls, path):
        with np.load(path, allow_pickle=False) as f:
            return cls({k: f[k] for k in f.files})

    def to_pandas(self):
        import pandas

        return pandas.DataFrame(self.columns)

    def __repr__(self):
        return f"Table({len(self)} runs, {int(self.failed.sum())} failed; columns {', '.join(self.names)})"


def _range(ensemble, start, stop):
    """One task: runs ``start`` to ``stop`` on this thread."""
    return ensemble.run(start, stop, threads=1)


def run(ensemble, backend="rayon", *, client=None, chunk=None, threads=None, progress=False):
    """Runs every run of ``ensemble`` on ``backend`` and returns the :class:`Table`.

    ``threads`` (rayon): None for every core. ``client`` (dask): a
    ``dask.distributed.Client`` (the current one by default); ``chunk`` (dask, ray):
    runs per task (by default about four tasks per worker thread, at least 100 runs
    each)."""
    n = len(ensemble)
    if backend == "rayon":
        return Table(ensemble.run(0, n, threads=threads, progress=progress))
    if backend == "loop":
        return Table.concat(Table(_range(ensemble, i, i + 1)) for i in range(n))
    if backend == "dask":
        from dask.distributed import get_client

        client = client or get_client()
        if chunk is None:
            workers = sum(client.nthreads().values()) or 1
            chunk = max(100, -(-n // (4 * workers)))
        starts = list(range(0, n, chunk))
        stops = [min(s + chunk, n) for s in starts]
        # The ensemble travels once to the cluster, not once per task. A fresh key each
        # call (hash=False): a hashed key is the same for the same ensemble, and a second
        # call could scatter it while the first call's copy is being released, which
        # Dask reports as lost dependencies.
        [remote] = client.scatter([ensemble], broadcast=True, hash=False)
        futures = client.map(_range, [remote] * len(starts), starts, stops, pure=False)
        return Table.concat(Table(part) for part in client.gather(futures))
    if backend == "ray":
        import ray

        if not ray.is_initialized():
            raise RuntimeError(
                "the ray backend needs a running Ray: call ray.init() first "
                "(ray.init(num_cpus=2) starts a local one, ray.init(address=...) joins a cluster)"
            )
        if chunk is None:
            workers = int(ray.cluster_resources().get("CPU", 1)) or 1
            chunk = max(100, -(-n // (4 * workers)))
        task = ray.remote(num_cpus=1)(_range)
        remote = ray.put(ensemble)
        refs = [task.remote(remote, s, min(s + chunk, n)) for s in range(0, n, chunk)]
        return Table.concat(Table(part) for part in ray.get(refs))
    raise ValueError(f"no backend {backend!r}; the backends are rayon, loop, dask and ray")
