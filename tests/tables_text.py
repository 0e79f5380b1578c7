"""The REBA and RULA tables as published text (cross-checked across independent public sources),
kept verbatim so that the package's numeric tables are checked against a separate transcription.
"""

from __future__ import annotations

import ast

REBA_TEXT = """\
TABLE_A[trunk 1-5][neck 1-3][legs 1-4]
[[1,2,3,4],[1,2,3,4],[3,3,5,6]]   trunk 1
[[2,3,4,5],[3,4,5,6],[4,5,6,7]]   trunk 2
[[2,4,5,6],[4,5,6,7],[5,6,7,8]]   trunk 3
[[3,5,6,7],[5,6,7,8],[6,7,8,9]]   trunk 4
[[4,6,7,8],[6,7,8,9],[7,8,9,9]]   trunk 5
TABLE_B[upper arm 1-6][lower arm 1-2][wrist 1-3]
[[1,2,2],[1,2,3]] [[1,2,3],[2,3,4]] [[3,4,5],[4,5,5]] [[4,5,5],[5,6,7]] [[6,7,8],[7,8,8]] [[7,8,8],[8,9,9]]
TABLE_C[score A 1-12][score B 1-12]
[1,1,1,2,3,3,4,5,6,7,7,7]
[1,2,2,3,4,4,5,6,6,7,7,8]
[2,3,3,3,4,5,6,7,7,8,8,8]
[3,4,4,4,5,6,7,8,8,9,9,9]
[4,4,4,5,6,7,8,8,9,9,9,9]
[6,6,6,7,8,8,9,9,10,10,10,10]
[7,7,7,8,9,9,9,10,10,11,11,11]
[8,8,8,9,10,10,10,10,10,11,11,11]
[9,9,9,10,10,10,11,11,11,12,12,12]
[10,10,10,11,11,11,11,12,12,12,12,12]
[11,11,11,11,12,12,12,12,12,12,12,12]
[12,12,12,12,12,12,12,12,12,12,12,12]
"""

RULA_TEXT = """\
TABLE_A[upper arm 1-6][lower arm 1-3][(wrist 1-4 − 1)·2 + (wrist twist 1-2 − 1)]
[[1,2,2,2,2,3,3,3],[2,2,2,2,3,3,3,3],[2,3,3,3,3,3,4,4]]
[[2,3,3,3,3,4,4,4],[3,3,3,3,3,4,4,4],[3,4,4,4,4,4,5,5]]
[[3,3,4,4,4,4,5,5],[3,4,4,4,4,4,5,5],[4,4,4,4,4,5,5,5]]
[[4,4,4,4,4,5,5,5],[4,4,4,4,4,5,5,5],[4,4,4,5,5,5,6,6]]
[[5,5,5,5,5,6,6,7],[5,6,6,6,6,7,7,7],[6,6,6,7,7,7,7,8]]
[[7,7,7,7,7,8,8,9],[8,8,8,8,8,9,9,9],[9,9,9,9,9,9,9,9]]
TABLE_B[neck 1-6][trunk 1-6][legs 1-2]
[[1,3],[2,3],[3,4],[5,5],[6,6],[7,7]]
[[2,3],[2,3],[4,5],[5,5],[6,7],[7,7]]
[[3,3],[3,4],[4,5],[5,6],[6,7],[7,7]]
[[5,5],[5,6],[6,7],[7,7],[7,7],[8,8]]
[[7,7],[7,7],[7,8],[8,8],[8,8],[8,8]]
[[8,8],[8,8],[8,8],[8,9],[9,9],[9,9]]
TABLE_C[min(score C, 8)][min(score D, 7)]
[1,2,3,3,4,5,5] [2,2,3,4,4,5,5] [3,3,3,4,4,5,6] [3,3,3,4,5,6,6]
[4,4,4,5,6,7,7] [4,4,5,6,6,7,7] [5,5,6,6,7,7,7] [5,5,6,7,7,7,7]
"""


def _rows(text: str) -> list[str]:
    return [line for line in text.splitlines() if line.strip()]


def _literal(line: str):
    """The list literal(s) at the start of a line, before any trailing label."""
    body = line.split("   ")[0].strip()
    return ast.literal_eval("[" + body.replace("] [", "],[") + "]")


def parse_tables() -> dict[str, list]:
    """Nested lists indexed [i-1][j-1]...: reba_a, reba_b, reba_c, rula_a, rula_b, rula_c."""
    reba = _rows(REBA_TEXT)
    rula = _rows(RULA_TEXT)
    assert reba[0].startswith("TABLE_A") and reba[6].startswith("TABLE_B")
    assert reba[8].startswith("TABLE_C") and len(reba) == 21
    reba_a = [_literal(line)[0] for line in reba[1:6]]
    reba_b = _literal(reba[7])
    reba_c = [_literal(line)[0] for line in reba[9:21]]
    assert rula[0].startswith("TABLE_A") and rula[7].startswith("TABLE_B")
    assert rula[14].startswith("TABLE_C") and len(rula) == 17
    rula_a = [_literal(line)[0] for line in rula[1:7]]
    rula_b = [_literal(line)[0] for line in rula[8:14]]
    rula_c = _literal(rula[15]) + _literal(rula[16])
    return {"reba_a": reba_a, "reba_b": reba_b, "reba_c": reba_c,
            "rula_a": rula_a, "rula_b": rula_b, "rula_c": rula_c}
