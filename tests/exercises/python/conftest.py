"""The Python variants of the exercises: each test file here runs against the student's
exercises/<folder>/python/exercise.py, or with --solution against the reference
solutions/<folder>/python/solution.py (the same tests for both; ctest runs the solutions,
tools/check-exercises.sh checks that every test case fails against the untouched stub).

A test file names its exercise (EXERCISE = "57.3.3", FOLDER = its folder) and gets the module
under test from the fixture `ex`; @pytest.mark.hint(n) names the README hint that helps, and a
failed test says what to read, as the C++ exercise programs do.
"""
import importlib.util
import pathlib

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[3]


def pytest_addoption(parser):
    parser.addoption("--solution", action="store_true",
                     help="test solutions/<folder>/python/solution.py instead of the student's "
                          "exercises/<folder>/python/exercise.py")


def pytest_configure(config):
    config.addinivalue_line("markers", "hint(n): the hint of the exercise's README that helps")


@pytest.fixture(scope="module")
def ex(request):
    """The module under test: the student's exercise.py, or the solution with --solution."""
    folder = request.module.FOLDER
    path = (SOURCE / "solutions" / folder / "python" / "solution.py"
            if request.config.getoption("--solution")
            else SOURCE / "exercises" / folder / "python" / "exercise.py")
    spec = importlib.util.spec_from_file_location(f"{folder}_{path.stem}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """After a failed test: "Read: <chapter> (section S) and hint N in <folder>/README.md"."""
    report = (yield).get_result()
    if report.when != "call" or not report.failed:
        return
    exercise = item.module.EXERCISE
    section = exercise.rsplit(".", 1)[0]
    chapters = sorted((SOURCE / "chapters").glob(f"{section}-*.md"))
    chapter = chapters[0].relative_to(SOURCE) if chapters else "chapter"
    hint = item.get_closest_marker("hint")
    report.sections.append(("what to read", (
        f"Read: {chapter} (section {section}) and "
        f"{f'hint {hint.args[0]}' if hint else 'the hints'} in "
        f"exercises/{item.module.FOLDER}/README.md")))
