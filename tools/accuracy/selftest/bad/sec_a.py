"""Self-test section a (tools/accuracy/test_generator.py)."""
from accuracy.study import Custom

TITLE = "Fake technique a"
ORDER = 20
INTRO = "A fake study with known rows."


def studies(ctx):
    return [Custom(id="fake_a", title="fake a", technique="fakea", backend="cpu",
                   command=["python3", "tools/accuracy/selftest/fake_study.py", "{out}",
                            "rows.csv", "a", "{quick}"],
                   csv="rows.csv", reference_label="the oracle", reference_image="ref.png"),
            Custom(id="fake_a2", title="fake a, second study", technique="fakea2",
                   backend="gl",
                   command=["python3", "tools/accuracy/selftest/fake_study.py", "{out}",
                            "rows.csv", "b"], csv="rows.csv", reference_label="the oracle")]
