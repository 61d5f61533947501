"""_uncached.py: what the prt and probe sections share (not a section: the generator skips
files starting with "_").

UncachedStudy is a Study whose sweep runs with the on-disk cache off. prt_bake, prt_reference
and ibl's GGX chain keep their results in the host's cache (docs/sdk.md "Cache"); a sweep's
repeats, and any later run of the atlas, would then time a cache load instead of the bake,
the reference or the prefilter. LIGHTGRAPH_CACHE_DIR names a regular file, which the host
refuses as a cache directory ("it is not a directory": one warning per render, the cache
disabled for that render, the render goes on), so every run computes what it times.
"""
import os

from accuracy.study import Study


def no_cache_path(ctx):
    """A regular file in the section's scratch directory (made once)."""
    path = os.path.join(ctx.tmp, "no-cache")
    if not os.path.isfile(path):
        with open(path, "w") as f:
            f.write("not a directory: LIGHTGRAPH_CACHE_DIR names this file so that the "
                    "host's on-disk cache is off for the sweep\n")
    return path


class UncachedStudy(Study):
    """A Study whose `lightgraph sweep` runs with the on-disk cache off (module doc)."""

    def command(self, ctx, outdir, repeat=None):
        return (["env", "LIGHTGRAPH_CACHE_DIR=" + no_cache_path(ctx)] +
                super().command(ctx, outdir, repeat))


def backend_available(ctx, backend):
    """Whether `lightgraph devices BACKEND` can make the device here (exit 0)."""
    import subprocess
    r = subprocess.run([ctx.lightgraph, "devices", backend], capture_output=True, text=True)
    return r.returncode == 0
