"""Self-test section b (tools/accuracy/test_generator.py)."""
from accuracy.study import Custom

TITLE = "Fake technique b"
ORDER = 10
INTRO = "A fake study with known rows."


def studies(ctx):
    return [Custom(id="fake_b", title="fake b", technique="fakeb", backend="cpu",
                   command=["python3", "tools/accuracy/selftest/fake_study.py", "{out}",
                            "rows.csv", "b", "{quick}"],
                   csv="rows.csv", reference_label="the oracle", reference_image="ref.png")]
