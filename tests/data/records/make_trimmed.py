"""Make CICLC_trim.v1 from the CSMIP V1 file CICLC.v1 shipped in the gmprocess 2.8.0 wheel
(gmprocess/data/demo/ci38457511/raw/CICLC.v1; public domain, see README.md).

Usage: python make_trimmed.py path/to/CICLC.v1   (writes CICLC_trim.v1 beside this script)

Each of the three channels keeps samples [FIRST, FIRST + N) (the window around the peaks);
the header fields that depend on the length are rewritten consistently: "No. of Points",
"Record Length", the data header count, integer-header values 28 and 33 (npts), real-header
value 3 (record length) and the peak time of "Max = ... at ... sec" / real-header value 8.
Everything else is copied byte for byte (CRLF line ends kept).
"""

import sys
from pathlib import Path

FIRST, N, COLS, WIDTH = 23400, 400, 8, 9


def trim_channel(block: list[str]) -> list[str]:
    k = next(i for i, ln in enumerate(block) if "Accelerogram points" in ln)
    npts = int(block[k].split()[0])
    rate = int(block[k].split()[4])
    vals = []
    for ln in block[k + 1:]:
        if ln.startswith("/&"):
            break
        vals.extend(ln[q:q + WIDTH] for q in range(0, len(ln.rstrip("\n")), WIDTH))
    vals = [v for v in vals if v.strip()]
    assert len(vals) == npts
    keep = vals[FIRST:FIRST + N]
    peak = max(range(N), key=lambda j: abs(float(keep[j])))
    t_peak = peak / rate
    out = block[:k]
    length_old = f"{npts / rate:7.3f}"
    length_new = f"{N / rate:7.3f}"
    for i, ln in enumerate(out):
        if ln.startswith("No. of Points"):
            ln = ln.replace(f"{npts:6d}", f"{N:6d}").replace(length_old, length_new)
        if ln.startswith("Units of uncor"):
            head, at = ln.split(" at ", 1)
            old_t = at.split("sec")[0]  # e.g. "  234.360 "
            new_t = f"{t_peak:.3f}".lstrip("0").rjust(len(old_t.rstrip())) + " "
            ln = head + " at " + new_t + "sec" + at.split("sec", 1)[1]
        out[i] = ln
    # integer header: 7 lines of 16I5 after the 13 text lines; real header: 7 lines of 8F10
    ints = [out[13 + r] for r in range(7)]
    for r, ln in enumerate(ints):
        fields = [ln[q:q + 5] for q in range(0, len(ln.rstrip("\n")), 5)]
        fields = [f"{N:5d}" if f.strip() == str(npts) else f for f in fields]
        out[13 + r] = "".join(fields) + "\n"
    reals = [out[20 + r] for r in range(7)]
    r0 = reals[0]
    f = [r0[q:q + 10] for q in range(0, len(r0.rstrip("\n")), 10)]
    f[2] = f"{N / rate:10.5f}"
    f[7] = f"{t_peak:10.5f}"
    out[20] = "".join(f) + "\n"
    out.append(block[k].replace(f"{npts:6d}", f"{N:6d}", 1))
    for q in range(0, N, COLS):
        out.append("".join(keep[q:q + COLS]) + "\n")
    out.append(next(ln for ln in block if ln.startswith("/&")))
    return out


def main(src: str) -> None:
    lines = Path(src).read_text().splitlines(keepends=True)
    blocks, cur = [], []
    for ln in lines:
        cur.append(ln)
        if ln.startswith("/&"):
            blocks.append(cur)
            cur = []
    out = [ln for b in blocks for ln in trim_channel(b)]
    # the published file has CRLF line ends: keep them
    Path(__file__).with_name("CICLC_trim.v1").write_text("".join(out), newline="\r\n")


if __name__ == "__main__":
    main(sys.argv[1])
