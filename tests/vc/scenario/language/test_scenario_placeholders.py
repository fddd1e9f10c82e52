"""``${...}`` placeholders are read by the reader of conditions, with its bounds, and compute within
MAX_MAGNITUDE: hostile arithmetic is a located problem, never a traceback."""

from __future__ import annotations

import pytest

from vc.input_limits import MAX_EXPRESSION_CHARACTERS, MAX_EXPRESSION_NESTING
from vc.scenario.language.expressions import Binary, ExpressionError, Grammar, Index, Name, parse, to_text, walk
from vc.scenario.language.placeholders import PlaceholderError, fill

VALUES = {"x": 1, "cam": [[1, 2], [3, 4]], "big": 10**15}


@pytest.mark.parametrize(("source", "message"), [
    # each of these ended in a RecursionError, MemoryError, OverflowError or ValueError traceback
    ("-" * 3000 + "1", f"more than {MAX_EXPRESSION_NESTING} parentheses, brackets and signs inside one another"),
    ("+".join(["1"] * 50_000), f"an expression holds at most {MAX_EXPRESSION_CHARACTERS:,}"),
    ("(" * 2000 + "1" + ")" * 2000, "inside one another"),
    ("*".join(["12345678901234567890"] * 250), f"an expression holds at most {MAX_EXPRESSION_CHARACTERS:,}"),
    ("*".join(["123456789012"] * 20), "is beyond 1e+15, the largest a placeholder may compute"),
    ("9" * 5000 + " / 3", f"an expression holds at most {MAX_EXPRESSION_CHARACTERS:,}"),
    ("1" + "0" * 400 + " / 3", "is beyond 1e+15, the largest an expression may hold"),
    ("big * big", "is beyond 1e+15, the largest a placeholder may compute"),
    ("x / 0.0000000000000000001 / 0.0000000000000000001", "the largest a placeholder may compute"),
    ("+".join(["x"] * 150), "more than 100 operators one inside the other"),
])
def test_hostile_arithmetic_is_a_located_problem(source: str, message: str) -> None:
    for text in ("${" + source + "}", "a text with ${" + source + "} inside"):
        with pytest.raises(PlaceholderError) as caught:
            fill(text, VALUES)
        assert message in caught.value.message
        assert caught.value.column == text.index("${") + 1
        assert len(caught.value.message) < 300  # the text is shortened, not echoed whole


def test_the_arithmetic_grammar_is_the_sum_of_the_condition_grammar_with_indexes() -> None:
    tree = parse("cam[x][0] + -(2 * x)", Grammar.ARITHMETIC)
    assert to_text(tree) == "(cam[x][0] + (-(2 * x)))"
    assert fill("${cam[x][0] + -(2 * x)}", VALUES) == 1
    assert fill("${+x}", VALUES) == 1
    assert fill("${cam[x - 1]}", VALUES) == [1, 2]
    with pytest.raises(PlaceholderError, match="unexpected '<'"):
        fill("${x < 2}", VALUES)  # comparisons belong into conditions


def test_a_condition_reads_an_element_of_an_array_datum_as_one_name() -> None:
    """``X1.MD34090[1]`` is documented for conditions; the reader refused the bracket."""
    tree = parse("X1.MD34090[1] > 0")
    assert isinstance(tree, Binary) and isinstance(tree.left, Name) and tree.left.text == "X1.MD34090[1]"
    assert not any(isinstance(node, Index) for node in walk(tree))
    with pytest.raises(ExpressionError, match="an index in a condition is a whole number"):
        parse("X1.MD34090[a] > 0")
