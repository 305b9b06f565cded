#!/usr/bin/env python3
"""Seed corpora for the libFuzzer harnesses (docs/robustness.md, "Fuzzing").

Seeds come from the real data sets in ../shared/data, the test fixtures, the repository's own
configuration files and, for the navaid format, recordings the simulator has just written
(passed with --recording). Multi-file inputs are packed as unpack_folder() reads them: a line
"=== <relative path>" starts each file. Usage:
    make_seeds.py --data ../shared/data --source . --out CORPUS_DIR [--recording DIR ...]
"""
import argparse
import gzip
import bz2
import pathlib
import re
import struct
import wave
import io

MAX_LINES = 40       # rows kept of each CSV / text table: seeds stay small, so fuzzing stays fast
MAX_BYTES = 64 * 1024


def head_lines(path, n=MAX_LINES):
    with open(path, 'rb') as f:
        lines = []
        for line in f:
            lines.append(line)
            if len(lines) >= n:
                break
    return b''.join(lines)


def pack(files):
    """files: list of (relative name, bytes)."""
    out = bytearray()
    for name, data in files:
        out += b'=== ' + name.encode() + b'\n' + data
        if not data.endswith(b'\n'):
            out += b'\n'
    return bytes(out)


class Corpus:
    def __init__(self, root):
        self.root = pathlib.Path(root)
        self.count = {}

    def add(self, harness, name, data):
        d = self.root / harness
        d.mkdir(parents=True, exist_ok=True)
        (d / ('seed-' + re.sub(r'[^A-Za-z0-9_.-]', '_', name))).write_bytes(data[:MAX_BYTES * 4])
        self.count[harness] = self.count.get(harness, 0) + 1


def nmea(c, data):
    for log in sorted((data / 'gpsd-nmea').glob('*.log')):
        c.add('fuzz_nmea_capture', log.name, head_lines(log, 200)[:MAX_BYTES])


def trajectories(c, data):
    files = sorted((data / 'evo-trajectories').glob('*.txt')) + sorted((data / 'evo-trajectories').glob('*.tum'))
    files += sorted((data / 'rpg-euroc-V1_02' / 'vislam_rp').glob('stamped_*.txt'))[:3]
    for f in files:
        c.add('fuzz_tum_trajectory', f.name, head_lines(f))


def euroc(c, data):
    root = data / 'euroc-V1_01-micro' / 'mav0'
    files = []
    for sensor in ('cam0', 'imu0', 'state_groundtruth_estimate0'):
        if (root / sensor / 'sensor.yaml').exists():
            files.append((f'mav0/{sensor}/sensor.yaml', (root / sensor / 'sensor.yaml').read_bytes()))
        if (root / sensor / 'data.csv').exists():
            files.append((f'mav0/{sensor}/data.csv', head_lines(root / sensor / 'data.csv', 12)))
    # Images are only checked to exist: empty files keep the seed small.
    for line in head_lines(root / 'cam0' / 'data.csv', 12).decode().splitlines()[1:]:
        fields = line.split(',')
        if len(fields) == 2:
            files.append((f'mav0/cam0/data/{fields[1].strip()}', b''))
    c.add('fuzz_euroc', 'V1_01', pack(files))
    imu_only = data / 'euroc-V1_02-imu' / 'mav0'
    c.add('fuzz_euroc', 'V1_02-imu', pack([(f'mav0/{s}/data.csv', head_lines(imu_only / s / 'data.csv', 12))
                                           for s in ('imu0', 'state_groundtruth_estimate0')] +
                                          [(f'mav0/{s}/sensor.yaml', (root / s / 'sensor.yaml').read_bytes())
                                           for s in ('imu0',)]))


def tum_rgbd(c, data):
    gt = (data / 'evo-trajectories' / 'freiburg1_xyz-groundtruth.txt')
    rows = [l for l in head_lines(gt, 60).decode().splitlines() if l and not l.startswith('#')][:10]
    stamps = [float(r.split()[0]) for r in rows]
    rgb = ''.join(f'{t:.6f} rgb/{t:.6f}.png\n' for t in stamps)
    depth = ''.join(f'{t + 0.01:.6f} depth/{t + 0.01:.6f}.png\n' for t in stamps)
    acc = ''.join(f'{t:.4f} -0.0730 9.7800 0.8520\n' for t in stamps)
    files = [('rgb.txt', ('# color images\n# file\n# timestamp filename\n' + rgb).encode()),
             ('depth.txt', ('# depth maps\n# file\n# timestamp filename\n' + depth).encode()),
             ('accelerometer.txt', ('# accelerometer data\n# file\n# timestamp ax ay az\n' + acc).encode()),
             ('groundtruth.txt', ('# ground truth trajectory\n# file\n# timestamp tx ty tz qx qy qz qw\n' +
                                  '\n'.join(rows) + '\n').encode())]
    files += [(f'rgb/{t:.6f}.png', b'') for t in stamps] + [(f'depth/{t + 0.01:.6f}.png', b'') for t in stamps]
    c.add('fuzz_tum_rgbd', 'fr1_xyz', pack(files))


def kalibr(c, source, data):
    text = (source / 'tests' / 'io' / 'fixtures' / 'kalibr_fixture.hpp').read_text()
    for i, m in enumerate(re.finditer(r'R"\((.*?)\)"', text, re.S)):
        c.add('fuzz_kalibr', f'fixture{i}', m.group(1).encode())
    for y in (data / 'euroc-V1_01-micro' / 'mav0').glob('*/sensor.yaml'):
        c.add('fuzz_kalibr', 'euroc-' + y.parent.name, y.read_bytes())


def occupancy_map(c, data):
    """A 48 x 40 crop of the real Willow office map, as P5 and as P2 (ASCII) PGM."""
    pgm = (data / 'ros-map-willow' / 'willow-full-0.05.pgm').read_bytes()
    m = re.match(rb'P5\s+(?:#[^\n]*\n\s*)*(\d+)\s+(\d+)\s+(\d+)\s', pgm)
    if not m:
        return
    w, h = int(m.group(1)), int(m.group(2))
    pixels = pgm[m.end():]
    x0, y0, cw, ch = w // 2, h // 2, 48, 40
    crop = b''.join(pixels[(y0 + r) * w + x0:(y0 + r) * w + x0 + cw] for r in range(ch))
    yaml = (data / 'ros-map-willow' / 'willow-full-0.05.yaml').read_text()
    yaml = re.sub(r'image:.*', 'image: map.pgm', yaml).encode()
    p5 = b'P5\n%d %d\n255\n' % (cw, ch) + crop
    p2 = b'P2\n%d %d\n255\n' % (cw, ch) + b'\n'.join(b' '.join(b'%d' % v for v in crop[r * cw:(r + 1) * cw])
                                                     for r in range(ch)) + b'\n'
    c.add('fuzz_occupancy_map', 'willow-p5', pack([('map.yaml', yaml), ('map.pgm', p5)]))
    c.add('fuzz_occupancy_map', 'willow-p2', pack([('map.yaml', yaml), ('map.pgm', p2)]))


def osm(c, data, source):
    """First byte: 0 .osm, 1 .osm.pbf, 2 .osm.gz, 3 .osm.bz2 (fuzz_osm.cpp)."""
    small = source / 'tests' / 'planning' / 'fixtures' / 'foot_street.osm'
    xml = small.read_bytes()
    c.add('fuzz_osm', 'foot_street.osm', b'\x00' + xml)
    c.add('fuzz_osm', 'foot_street.osm.gz', b'\x02' + gzip.compress(xml, mtime=0))
    c.add('fuzz_osm', 'foot_street.osm.bz2', b'\x03' + bz2.compress(xml))
    pbfs = sorted((data / 'osm').glob('*.osm.pbf'), key=lambda p: p.stat().st_size)
    if pbfs and pbfs[0].stat().st_size <= 256 * 1024:
        c.add('fuzz_osm', pbfs[0].name, b'\x01' + pbfs[0].read_bytes())


def wav(c):
    for rate, channels in ((22050, 1), (16000, 2)):
        buf = io.BytesIO()
        with wave.open(buf, 'wb') as w:
            w.setnchannels(channels)
            w.setsampwidth(2)
            w.setframerate(rate)
            w.writeframes(b''.join(struct.pack('<h', (i * 997) % 20000 - 10000) for i in range(64 * channels)))
        c.add('fuzz_wav', f'{rate}-{channels}', buf.getvalue())


def tables(c, source):
    """First byte: 0 targets, 1 obstacle scans, 2 guidance timeline, 3 ablation matrix (fuzz_tables.cpp)."""
    c.add('fuzz_tables', 'targets', b'\x00' +
          b'name,class,family,tag_id,tag_size_m,cx,cy,cz,hx,hy,hz,tx,ty,tz,qw,qx,qy,qz\n'
          b'cup,cup,tag36h11,3,0.04,1.5,0.2,0.9,0.04,0.04,0.06,1.46,0.2,0.95,1,0,0,0\n')
    c.add('fuzz_tables', 'obstacle-scan', b'\x01' +
          b't_ns,ground,ransac,obstacle_points,drop_off_points\n1000000000,1,1,12,0\n1033333333,1,0,0,3\n')
    c.add('fuzz_tables', 'guidance', b'\x02' +
          b't_s,type,action,reason,confidence,heading_deg,steering_deg,rumble,hand,event,value\n'
          b'0.5,path,forward,,0.9,12.5,,,,,\n1.0,event,,,,,,,,mode,"rgbd-vio"\n')
    for y in sorted((source / 'experiments' / 'ablations').glob('*.yaml')):
        c.add('fuzz_tables', 'ablation-' + y.name, b'\x03' + y.read_bytes())


def config(c, source):
    for y in sorted((source / 'experiments' / 'devices').glob('*.yaml')):
        c.add('fuzz_config', y.name, y.read_bytes() + b'\n===\nestimator.window_size=12\ndevice.name=belt\n')
    c.add('fuzz_config', 'overrides-only', b'{}\n===\nestimator.depth.enabled=false\nfrontend.rate_hz=15\n')


def crc16(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def frame(ftype, seq, payload):
    body = bytes([len(payload), ftype]) + struct.pack('<H', seq) + payload
    return b'\xA5\x5A' + body + struct.pack('<H', crc16(body))


def device_link(c):
    assert crc16(b'123456789') == 0x29B1
    pattern = bytes([1, 2]) + struct.pack('<BhHHH', 0, 800, 200, 100, 1100) + struct.pack('<BhHHH', 3, 300, 0, 0, 900)
    host = [frame(0x03, 1, b'\x01'), frame(0x01, 2, pattern), frame(0x01, 2, pattern), frame(0x02, 4, b''),
            frame(0x01, 1, bytes([1, 0]))]
    device = [frame(0x81, 7, struct.pack('<HB', 2, 0)), frame(0x82, 8, struct.pack('<HBB', 3, 4, 9)),
              frame(0x83, 9, struct.pack('<HBBHH', 1, 1, 3, 100, 2))]
    stream = b''.join(host)
    c.add('fuzz_device_link', 'host-frames', b'\x07' + stream)
    c.add('fuzz_device_link', 'garbage-between', b'\x00' + b'\x00\xA5' + stream[:11] + b'\xA5\x5A\xff' + stream)
    c.add('fuzz_device_link', 'device-frames', b'\x03' + b''.join(device))
    c.add('fuzz_device_firmware', 'belt', bytes([1, 5, 9]) + stream)
    c.add('fuzz_device_firmware', 'wheel', bytes([4, 1, 0]) + frame(0x03, 1, b'\x01') +
          frame(0x01, 2, bytes([4, 1]) + struct.pack('<BhHHH', 0, -1234, 0, 0, 500)))


def ros_bags(c, data, src):
    """The real lz4 /tf bag, and the test fixtures' bags (uncompressed ones mutate best), written
    by Debian's python3-rosbag through tests/io/fixtures/make_ros_bags.py."""
    tf = data / 'ros-bags' / 'tf_example.bag'
    if tf.exists():
        c.add('fuzz_ros_bag', 'tf_example', tf.read_bytes())
    import subprocess
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        made = subprocess.run(['/usr/bin/python3', str(src / 'tests/io/fixtures/make_ros_bags.py'), tmp],
                              capture_output=True)
        if made.returncode != 0:
            print('make_seeds: no fixture bags (python3-rosbag missing?)')
            return
        for name in ('two_imus', 'odometry', 'split_imu', 'encodings'):
            c.add('fuzz_ros_bag', name, (pathlib.Path(tmp) / (name + '.bag')).read_bytes())


def recordings(c, recordings):
    for rec in recordings:
        rec = pathlib.Path(rec)
        files = []
        for f in sorted(rec.rglob('*')):
            if not f.is_file():
                continue
            rel = f.relative_to(rec).as_posix()
            if f.suffix == '.csv':
                files.append((rel, head_lines(f, 12)))
            elif f.suffix == '.yaml' or (f.suffix == '.png' and '/' in rel):  # frame images, not figures
                files.append((rel, f.read_bytes()))
        c.add('fuzz_navaid_recording', rec.name, pack(files))
        if (rec / 'targets.csv').exists():
            c.add('fuzz_tables', 'targets-' + rec.name, b'\x00' + (rec / 'targets.csv').read_bytes())


if __name__ == '__main__':
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--data', required=True)
    ap.add_argument('--source', required=True)
    ap.add_argument('--out', required=True)
    ap.add_argument('--recording', action='append', default=[])
    args = ap.parse_args()
    data_root = pathlib.Path(args.data)
    src = pathlib.Path(args.source)
    corpus = Corpus(args.out)
    nmea(corpus, data_root)
    trajectories(corpus, data_root)
    euroc(corpus, data_root)
    tum_rgbd(corpus, data_root)
    kalibr(corpus, src, data_root)
    occupancy_map(corpus, data_root)
    ros_bags(corpus, data_root, src)
    osm(corpus, data_root, src)
    wav(corpus)
    tables(corpus, src)
    config(corpus, src)
    device_link(corpus)
    recordings(corpus, args.recording)
    for harness, n in sorted(corpus.count.items()):
        print(f'make_seeds: {harness}: {n} seeds')
