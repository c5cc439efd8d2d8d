"""sigrok-cli runs the tformat and biss decoders (sigrok/decoders) over captures built here
from the library's own encoders (captures.py) and turned into .sr files by sigrok-cli's binary
input; every frame's annotations must match the values the capture was built from, and a
corrupted capture must give CRC-bad annotations, exit status 0 and no Python error."""

import os
import re
import shutil
import subprocess
import sys

import pytest

from motionbus import AlmcBit, biss, tformat
import captures

HERE = os.path.dirname(os.path.abspath(__file__))
DECODERS = os.path.join(HERE, '..', '..', 'sigrok', 'decoders')
SIGROK_CLI = os.environ.get('SIGROK_CLI', 'sigrok-cli')


def env():
    e = dict(os.environ)
    e['SIGROKDECODE_DIR'] = os.path.abspath(DECODERS)
    import motionbus
    pkg = os.path.dirname(os.path.dirname(os.path.abspath(motionbus.__file__)))
    e['PYTHONPATH'] = pkg + os.pathsep + e.get('PYTHONPATH', '')
    return e


def make_sr(tmp_path, name, samples, channels, rate):
    raw = tmp_path / (name + '.bin')
    raw.write_bytes(samples)
    sr = tmp_path / (name + '.sr')
    r = subprocess.run([SIGROK_CLI, '-I', 'binary:numchannels=%d:samplerate=%d' % (channels, rate),
                        '-i', str(raw), '-o', str(sr)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return sr


def decode(path, pds, show):
    r = subprocess.run([SIGROK_CLI, '-i', str(path), '-P', pds, '-A', show,
                        '--protocol-decoder-samplenum'], capture_output=True, text=True, env=env())
    assert r.returncode == 0, r.stderr
    assert 'Traceback' not in r.stderr and 'srd:' not in r.stderr, r.stderr
    out = []
    for line in r.stdout.splitlines():
        m = re.match(r'(\d+)-(\d+) \S+: (.*)$', line)
        assert m, line
        out.append((int(m.group(1)), int(m.group(2)), m.group(3)))
    return out


TF_PD = 'uart:rx=0:baudrate=2500000,tformat'


def frames_of(anns):
    """The annotations grouped per frame (a Request / Response line starts one)."""
    groups = []
    for ss, es, text in anns:
        if text.startswith('Request ') or text.startswith('Response '):
            groups.append(Group([text], (ss, es)))
        elif groups:
            groups[-1].append(text)
    return groups


class Group(list):
    """A frame's annotation texts, with the frame's sample range."""
    def __init__(self, texts, span):
        super().__init__(texts)
        self.span = span


def check_response(group, r):
    did = '%X' % int(r.id)
    assert group[0].startswith('Response ID' + did)
    assert 'CF: 0x%02X ID%s' % (r.cf, did) in group
    assert 'CRC good: 0x%02X' % r.crc in group
    if int(r.id) in (0, 3, 7, 8, 12):
        assert 'ABS: %d' % r.abs in group
    if int(r.id) in (1, 3):
        assert 'ABM: %d' % r.abm in group
    if int(r.id) in (2, 3):
        assert 'ENID: 0x%02X' % r.enid in group
    if int(r.id) == 3:
        assert 'ALMC: 0x%02X' % r.almc in group
        alarms = sorted(t for t in group if t.startswith('ALMC: ') and '(' in t)
        assert len(alarms) == len(r.alarms)
        for a in r.alarms:
            assert any('(%s)' % a.name.upper() in t for t in alarms)
    if int(r.id) in (6, 13):
        assert 'ADF: 0x%02X' % r.address in group
        assert 'EDF: 0x%02X' % r.edf in group
        assert any(t.startswith('EEPROM ') and 'address 0x%02X data 0x%02X' % (r.address, r.edf)
                   in t for t in group)


@pytest.mark.parametrize('corrupt', [False, True])
def test_tformat(tmp_path, corrupt):
    samples, expected = captures.tformat_capture(corrupt=corrupt)
    sr = make_sr(tmp_path, 'tformat', samples, 1, captures.TF_RATE)
    groups = frames_of(decode(sr, TF_PD, 'tformat'))
    g = iter(groups)
    for e in expected:
        req = next(g)
        cf = e['request_bytes'][0]
        did = [tformat.control_field(i) for i in range(16)].index(cf)
        assert req[0].startswith('Request ID%X (CF 0x%02X)' % (did, cf)), req
        assert req.span == e['request_span']
        if len(e['request_bytes']) > 1:
            assert 'CRC good: 0x%02X' % e['request_bytes'][-1] in req
            assert 'ADF: 0x%02X' % e['request_bytes'][1] in req
        if cf == 0x2A:
            assert 'Abnormal request: tformat_unknown_data_id' in req
        assert ('Delimiter error (stop bit 0)' in req) == e['delimiter_error'], req
        if 'reply_bytes' not in e:
            assert any(t.startswith('Missing response to ID') for t in req), req
            continue
        if e['reply'] is None:  # corrupted: rejected with its CRC evidence, inside the request's group
            assert any(t.startswith('CRC bad: expected 0x') for t in req), req
            assert 'Rejected response: crc_mismatch' in req
            continue
        resp = next(g)
        assert resp.span == e['reply_span']
        check_response(resp, e['reply'])
        if cf == 0x2A or e['delimiter_error']:
            assert 'ID3 reply to an abnormal request' in resp[0]
        if e['delimiter_error']:
            assert e['reply'].ca1 and 'SF: CA1 request delimiter error' in resp
    assert next(g, None) is None
    if not corrupt:
        # the capture's last ID3 reply carries the battery alarm set before it
        assert expected[-1]['reply'].alarms == [AlmcBit.be]


@pytest.mark.parametrize('tail', ['unanswered', 'cut'])
def test_tformat_missing_response_at_the_end_of_the_capture(tmp_path, tail):
    """The capture's last request is unanswered: flagged once the line has been idle longer
    than gap_us (10 us) in the capture (uart's IDLE packets), not flagged when the capture
    ends sooner (1.6 us after it: the response may have been cut off)."""
    samples, expected = captures.tformat_capture(tail=tail)
    sr = make_sr(tmp_path, 'tformat', samples, 1, captures.TF_RATE)
    anns = decode(sr, TF_PD, 'tformat')
    groups = frames_of(anns)
    last = groups[-1]
    assert last[0] == 'Request ID0 (CF 0x02)' and last.span == expected[-1]['request_span'], last
    flagged = [(ss, es) for ss, es, t in anns if t == 'Missing response to ID0 request']
    if tail == 'unanswered':
        assert 'Missing response to ID0 request' in last, last
        assert flagged[-1] == expected[-1]['request_span']
    else:
        assert not any(t.startswith('Missing') for t in last), last
    # the unanswered request inside the capture is flagged either way
    inner = [e['request_span'] for e in expected[:-1] if 'reply_bytes' not in e]
    assert len(inner) == 1 and inner[0] in flagged


def biss_check(anns, layout, frames, bad_frame=None, line_delay=2):
    chain = layout if isinstance(layout, list) else [layout]
    heads = [i for i, (_, _, t) in enumerate(anns) if t.startswith('Frame: ')]
    assert len(heads) == len(frames)
    for k, (values, cds, cdm, *span) in enumerate(frames):
        end = heads[k + 1] if k + 1 < len(heads) else len(anns)
        texts = [t for _, _, t in anns[heads[k]:end]]
        if span:  # the frame's samples: from MA's first falling edge to the last clock's end
            assert anns[heads[k]][:2] == span[0], (anns[heads[k]], span)
        assert 'CDM: %d' % int(cdm) in texts
        if k == bad_frame:
            assert texts[0].startswith('Frame: CRC bad'), texts
            assert any(t.startswith('CRC bad: expected 0x') for t in texts), texts
            continue
        assert 'CDS: %d' % int(cds) in texts
        if line_delay:
            assert 'Line delay: %d bits' % line_delay in texts
        assert 'Ack' in texts and 'Start' in texts
        for i, (lay, v) in enumerate(zip(chain, values)):
            assert 'Slave %d single-turn: %d' % (i, v.single_turn) in texts
            if lay.multi_turn_bits:
                assert 'Slave %d multi-turn: %d' % (i, v.multi_turn) in texts
            assert any(t.startswith('Slave %d CRC good: ' % i) for t in texts), texts
    return [t for _, _, t in anns if t.startswith('Register ')]


def test_biss_single_slave(tmp_path):
    layout = biss.SlaveLayout(single_turn_bits=26)
    positions = [[biss.SlaveValues(single_turn=v)] for v in (0, 1, 0x2ABCDEF, 0x3FFFFFF, 12345)]
    samples, frames, _ = captures.biss_capture(layout, positions)
    sr = make_sr(tmp_path, 'biss', samples, 2, captures.BISS_RATE)
    anns = decode(sr, 'biss:ma=0:slo=1:chain=26', 'biss')
    biss_check(anns, layout, frames)
    # each field over its bits: line delay 2, Ack 1, Start, CDS, then 26 data bits, nE, nW, CRC
    clock = 2 * captures.BISS_HALF
    for (values, _, _, (first, _)) in frames:
        pos = {t.split(':')[0]: (a, b) for a, b, t in anns if first <= a < first + 50 * clock}
        assert pos['Slave 0 single-turn'] == (first + 5 * clock, first + 31 * clock)
        assert pos['Slave 0 CRC good'] == (first + 33 * clock, first + 39 * clock)
        assert pos['Start'] == (first + 3 * clock, first + 4 * clock)


def test_biss_chain_and_corrupt_frame(tmp_path):
    crc = biss.crc_from_biss_notation(0x43)
    chain = [biss.SlaveLayout(multi_turn_bits=12, single_turn_bits=13, crc=crc),
             biss.SlaveLayout(single_turn_bits=18, crc=crc)]
    positions = [[biss.SlaveValues(multi_turn=k * 7, single_turn=k * 1000 + 1),
                  biss.SlaveValues(single_turn=0x3FFFF - k)] for k in range(4)]
    samples, frames, _ = captures.biss_capture(chain, positions, corrupt_frame=2)
    sr = make_sr(tmp_path, 'chain', samples, 2, captures.BISS_RATE)
    anns = decode(sr, 'biss:ma=0:slo=1:chain=12+13/18:crc_poly=0x43', 'biss')
    biss_check(anns, chain, frames, bad_frame=2)


def test_biss_register_read(tmp_path):
    layout = biss.SlaveLayout(single_turn_bits=26)
    regs = bytes(range(0x40, 0x80))
    n = biss.ControlMaster.frames_for(1) + 4
    positions = [[biss.SlaveValues(single_turn=k)] for k in range(n)]
    samples, frames, master = captures.biss_capture(layout, positions,
                                                    register_read=(0, 0x12, regs))
    assert master.data == bytes([regs[0x12]])
    sr = make_sr(tmp_path, 'reg', samples, 2, captures.BISS_RATE)
    reg = biss_check(decode(sr, 'biss:ma=0:slo=1:chain=26', 'biss'), layout, frames)
    assert reg == ['Register read slave 0 address 0x12 CRC4 0x%X good, read acknowledged'
                   % biss.header_crc(0, 0x12),
                   'Register read address 0x12 data 0x%02X CRC4 0x%X good'
                   % (regs[0x12], biss.data_crc(regs[0x12]))]


TB = os.path.join(HERE, '..', 'captures', 'tb.v')


def vcd_lines_only(src, dst, names):
    """The testbench's VCD with only its 1-bit lines `names` (libsigrok 0.5's VCD input reads
    the file's other variables, vectors and reals, as garbage)."""
    keep, out, header = set(), [], True
    for line in open(src):
        s = line.strip()
        if header:
            m = re.match(r'\$var \S+ 1 (\S+) (\S+) \$end', s)
            if s.startswith('$var'):
                if m and m.group(2) in names:
                    keep.add(m.group(1))
                    out.append(s)
                continue
            out.append(s)
            header = '$enddefinitions' not in s
        elif s and (s[0] == '#' or s[0] == '$' or (s[0] in '01xz' and s[1:] in keep)):
            out.append(s)
    with open(dst, 'w') as f:
        f.write('\n'.join(out) + '\n')


@pytest.mark.skipif(not (shutil.which('iverilog') and shutil.which('vvp')),
                    reason='needs Icarus Verilog')
def test_icarus_testbench_vcd(tmp_path):
    subprocess.run(['iverilog', '-g2005', '-o', 'tb.vvp', TB], cwd=tmp_path, check=True)
    subprocess.run(['vvp', '-n', 'tb.vvp'], cwd=tmp_path, check=True, stdout=subprocess.DEVNULL)
    vcd = tmp_path / 'lines.vcd'
    vcd_lines_only(tmp_path / 'capture.vcd', vcd, {'ma', 'slo', 'tf_line', 'mb_line'})
    sr = tmp_path / 'tb.sr'
    r = subprocess.run([SIGROK_CLI, '-I', 'vcd:downsample=10000', '-i', str(vcd), '-o', str(sr)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    # The values the testbench built its frames from.
    source = open(TB).read()
    positions = [int(v) for v in re.findall(r"biss_frame\(32'd(\d+)\)", source)]
    reply = bytes.fromhex(re.search(r"88'h([0-9A-Fa-f]{22});\s*fork", source).group(1))
    assert len(positions) == 2
    frames = [([biss.SlaveValues(single_turn=p)], False, False) for p in positions]
    anns = decode(sr, 'biss:ma=ma:slo=slo:chain=32', 'biss')
    biss_check(anns, biss.SlaveLayout(single_turn_bits=32), frames, line_delay=0)
    groups = frames_of(decode(sr, 'uart:rx=tf_line:baudrate=2500000,tformat', 'tformat'))
    assert len(groups) == 2
    assert groups[0][0] == 'Request ID3 (CF 0x1A)'
    check_response(groups[1], tformat.decode_response(reply))


def probe_dir(tmp_path):
    """The decoders and the test probe stacked on them, in one SIGROKDECODE_DIR."""
    d = tmp_path / 'decoders'
    shutil.copytree(DECODERS, d)
    shutil.copytree(os.path.join(HERE, 'probe'), d / 'mbprobe',
                    ignore=shutil.ignore_patterns('__pycache__'))
    return d


def test_python_output_for_stacked_decoders(tmp_path, monkeypatch):
    monkeypatch.setattr(sys.modules[__name__], 'DECODERS', str(probe_dir(tmp_path)))
    samples, expected = captures.tformat_capture(corrupt=True)
    sr = make_sr(tmp_path, 'tformat', samples, 1, captures.TF_RATE)
    got = [t for _, _, t in decode(sr, TF_PD + ',mbprobe', 'mbprobe')]
    want = []
    for e in expected:
        q = e['request_bytes']
        err = 'tformat_unknown_data_id' if q[0] == 0x2A else None
        want.append('REQUEST cf=0x%02X error=%s' % (q[0], err))
        if 'reply_bytes' not in e:
            want.append('MISSING cf=0x%02X' % q[0])
        elif e['reply'] is None:
            want.append('ERROR crc_mismatch')
        else:
            r = e['reply']
            want.append('RESPONSE id=%d abs=%d abm=%d id3_reply=%s' % (
                int(r.id), r.abs, r.abm, int(r.id) == 3 and q[0] != 0x1A))
    assert got == want

    layout = biss.SlaveLayout(single_turn_bits=26)
    regs = bytes(range(0x40, 0x80))
    n = biss.ControlMaster.frames_for(1) + 2
    positions = [[biss.SlaveValues(single_turn=k * 3)] for k in range(n)]
    samples, frames, _ = captures.biss_capture(layout, positions, register_read=(0, 0x12, regs))
    sr = make_sr(tmp_path, 'biss', samples, 2, captures.BISS_RATE)
    got = [t for _, _, t in decode(sr, 'biss:ma=0:slo=1:chain=26,mbprobe', 'mbprobe')]
    want = ['FRAME st=%d cds=%d cdm=%d' % (v[0].single_turn, int(cds), int(cdm))
            for v, cds, cdm, _ in frames]
    frames_only = [t for t in got if t.startswith('FRAME')]
    assert frames_only == want
    assert [t for t in got if not t.startswith('FRAME')] == [
        'REGISTER header address=0x12 data=0x00',
        'REGISTER byte address=0x12 data=0x%02X' % regs[0x12]]


def test_noise_gives_annotations_not_exceptions(tmp_path):
    """Random bytes on a T-format line (in valid UART framing, random gaps) and random SLO bits
    under a regular MA clock: both decoders annotate what they find, sigrok-cli exits 0 and no
    Python error reaches stderr (decode() checks both)."""
    import random
    rnd = random.Random(26)
    bits = [1] * 40
    for _ in range(3000):
        bits.extend(tformat.encode_line(bytes([rnd.randrange(256)]), rnd.choice((0, 0, 0, 2, 40))))
    sr = make_sr(tmp_path, 'tf_noise', bytes(b for b in bits for _ in range(8)), 1, captures.TF_RATE)
    texts = [t for _, _, t in decode(sr, TF_PD, 'tformat')]
    assert sum(t.startswith('Request ') for t in texts) > 100
    assert any(t.startswith('Rejected response: ') for t in texts)

    out = bytearray([3] * 40)
    for _ in range(200):
        for _ in range(rnd.randrange(4, 90)):
            b = rnd.randrange(2) << 1
            out.extend([b] * captures.BISS_HALF + [b | 1] * captures.BISS_HALF)
        out.extend([rnd.randrange(2)] * 200 + [3] * 80)
    sr = make_sr(tmp_path, 'biss_noise', bytes(out), 2, captures.BISS_RATE)
    texts = [t for _, _, t in decode(sr, 'biss:ma=0:slo=1:chain=12+13/18', 'biss')]
    assert sum(t.startswith('Frame: ') or t.startswith('No frame: ') for t in texts) == 200
