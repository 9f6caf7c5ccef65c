from hypothesis import given, settings, strategies as st

from hw.drivers.hiwonder_protocol import Cmd, Frame, FrameParser, checksum, encode, i8, u16

MOVE = bytes.fromhex("55 55 01 07 01 F4 01 E8 03 16")
POS_READ = bytes.fromhex("55 55 01 03 1C DF")
POS_REPLY = bytes.fromhex("55 55 01 05 1C F4 01 E8")


def test_reference_worked_examples():
    assert encode(1, Cmd.MOVE_TIME_WRITE, u16(500) + u16(1000)) == MOVE
    assert encode(1, Cmd.POS_READ) == POS_READ
    assert encode(1, Cmd.POS_READ, u16(500)) == POS_REPLY
    assert checksum(MOVE[2:-1]) == 0x16


def test_parser_reads_the_examples_and_negative_offsets():
    frames = FrameParser().feed(MOVE + POS_READ + POS_REPLY)
    assert frames == [Frame(1, 1, bytes.fromhex("F4 01 E8 03")), Frame(1, 28, b""), Frame(1, 28, bytes.fromhex("F4 01"))]
    assert i8(-1) == 0xFF and i8(-125) == 0x83  # +256, not +255


def test_parser_handles_split_delivery():
    p = FrameParser()
    out = []
    for b in MOVE + POS_REPLY:
        out += p.feed(bytes([b]))
    assert [f.cmd for f in out] == [1, 28]


FRAMES = st.builds(lambda i, c, p: encode(i, c, bytes(p)), st.integers(0, 253), st.sampled_from(list(Cmd)),
                   st.lists(st.integers(0, 255), max_size=4))


@settings(max_examples=150, deadline=None)
@given(st.binary(max_size=64), FRAMES, st.lists(st.integers(1, 16), max_size=6))
def test_garbage_never_raises_and_the_next_valid_frame_is_found(garbage, frame, cuts):
    p = FrameParser()
    stream = garbage + frame + frame
    got, pos = [], 0
    for c in cuts + [len(stream)]:
        got += p.feed(stream[pos:pos + c])
        pos += c
    got += p.feed(stream[pos:])
    # the garbage may swallow the first copy at most; the second always comes through intact
    assert got and got[-1].encode() == frame
