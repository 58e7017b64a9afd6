"""The report of `colmap-lidar automatic_reconstructor` (stage "report").

Reads what the pipeline left in a workspace and writes one self-contained
HTML page (figures embedded as base64 PNG) plus the same figures as PNG files:
  pipeline/stages.json      stage timings and peak memory;
  eval/poses_*.json         pose errors (pose_evaluator JSON);
  eval/trajectories.csv     camera centres: ground truth, priors, refined;
  eval/mesh_*.json          precision / recall / F per threshold;
  eval/mesh_*_precision.ply, eval/mesh_*_recall.ply
                            samples coloured by distance (mesh_evaluator);
  database.db               ext_line_segments / ext_line_track_elements for
                            the line overlays;
  sparse/refined            (counts only, from stages.json notes).
Missing inputs leave their section out with a sentence saying why; the page
is always written. This file is compiled into colmap-lidar (report.cc) and
run with Debian's python3, numpy and matplotlib.

Usage: python3 report.py WORKSPACE DATASET OUTPUT_DIR
"""

import base64
import csv
import html
import json
import math
import os
import sqlite3
import struct
import sys

import numpy as np
import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

POSE_ROWS = [
    ('prior', 'none', 'Prior poses (input)'),
    ('refined', 'none', 'Ours, refined (no alignment)'),
    ('refined', 'sim3', 'Ours, refined (sim3 alignment)'),
    ('colmap_mapper', 'sim3', 'Stock COLMAP mapper, no priors (sim3)'),
]
MESH_METHODS = [
    ('ours', 'Ours: LIDAR-MVS + lines, refined poses'),
    ('lidar_poisson', 'LIDAR only: Poisson on the registered LIDAR cloud'),
]


def load_json(path):
    if not os.path.isfile(path):
        return None
    with open(path) as stream:
        return json.load(stream)


def esc(text):
    return html.escape(str(text))


def fmt(value, digits=3):
    if value is None:
        return '-'
    if isinstance(value, float):
        if math.isnan(value):
            return '-'
        return f'{value:.{digits}f}'
    return str(value)


class Report:
    def __init__(self, workspace, dataset, output_dir):
        self.workspace = workspace
        self.dataset = dataset
        self.output_dir = output_dir
        self.sections = []
        self.num_figures = 0

    def figure(self, fig, name, caption):
        path = os.path.join(self.output_dir, name + '.png')
        fig.savefig(path, dpi=100)
        plt.close(fig)
        with open(path, 'rb') as stream:
            data = base64.b64encode(stream.read()).decode('ascii')
        self.num_figures += 1
        return (f'<figure><img src="data:image/png;base64,{data}" '
                f'alt="{esc(caption)}"><figcaption>{esc(caption)} '
                f'({esc(name)}.png)</figcaption></figure>')

    def section(self, title, body):
        self.sections.append(f'<h2>{esc(title)}</h2>\n{body}')

    # ---- Stage timings.
    def stages(self):
        data = load_json(os.path.join(self.workspace, 'pipeline',
                                      'stages.json'))
        if not data or not data.get('stages'):
            self.section('Stages', '<p>No stage has finished yet.</p>')
            return
        rows = []
        total_wall = total_cpu = 0.0
        peak = 0
        for stage in data['stages']:
            total_wall += stage['wall_seconds']
            total_cpu += stage['cpu_seconds']
            peak = max(peak, stage['peak_memory_bytes'])
            rows.append(
                f'<tr><td>{esc(stage["stage"])}</td>'
                f'<td>{stage["wall_seconds"]:.1f}</td>'
                f'<td>{stage["cpu_seconds"]:.1f}</td>'
                f'<td>{stage["peak_memory_bytes"] / 2**20:.0f}</td>'
                f'<td>{esc(stage["finished_at"])}</td>'
                f'<td>{esc(stage["note"])}</td></tr>')
        rows.append(f'<tr class="total"><td>total</td>'
                    f'<td>{total_wall:.1f}</td><td>{total_cpu:.1f}</td>'
                    f'<td>{peak / 2**20:.0f}</td><td></td><td></td></tr>')
        body = ('<p>Wall and CPU seconds of each stage (CPU includes the '
                'stock colmap processes it ran) and the peak resident memory '
                'of the process or of one colmap child during the stage. '
                f'{os.cpu_count()} cores.</p>'
                '<table><tr><th>stage</th><th>wall s</th><th>CPU s</th>'
                '<th>peak MiB</th><th>finished (UTC)</th><th>outcome</th>'
                '</tr>' + '\n'.join(rows) + '</table>')
        self.section('Stages', body)

    # ---- Poses.
    def poses(self):
        eval_dir = os.path.join(self.workspace, 'eval')
        rows = []
        errors = {}
        for name, alignment, label in POSE_ROWS:
            data = load_json(os.path.join(
                eval_dir, f'poses_{name}_{alignment}.json'))
            if data is None:
                continue
            position = data['position_error_m']
            rotation = data['rotation_error_deg']
            rows.append(
                f'<tr><td>{esc(label)}</td>'
                f'<td>{data["num_matched"]} / '
                f'{data["num_ground_truth_frames"]}</td>'
                f'<td>{fmt(position["mean"], 4)}</td>'
                f'<td>{fmt(position["median"], 4)}</td>'
                f'<td>{fmt(position["rmse"], 4)}</td>'
                f'<td>{fmt(position["max"], 4)}</td>'
                f'<td>{fmt(rotation["mean"], 3)}</td>'
                f'<td>{fmt(rotation["max"], 3)}</td></tr>')
            errors[label] = np.array(
                [image['position_error_m'] for image in data['images']])
        if not rows:
            self.section('Camera poses',
                         '<p>No pose evaluation: the recording has no '
                         'poses_gt.txt, or the evaluate stage has not run.'
                         '</p>')
            return
        body = ('<p>Camera centre error against the ground truth (metres) '
                'and rotation error (degrees) per registered image. "No '
                'alignment" compares the poses as estimated, in the world '
                'frame of the priors; sim3 first aligns the camera centres '
                'to the ground truth (Umeyama), which is how a model without '
                'metric priors (stock COLMAP) can be compared at all.</p>'
                '<table><tr><th>poses</th><th>images / GT frames</th>'
                '<th>mean m</th><th>median m</th><th>RMSE m</th><th>max m</th>'
                '<th>mean deg</th><th>max deg</th></tr>' + '\n'.join(rows) +
                '</table>')
        body += self.trajectory_figure(eval_dir)
        if errors:
            fig, ax = plt.subplots(figsize=(9, 4))
            all_errors = np.concatenate(list(errors.values()))
            positive = all_errors[all_errors > 0]
            # All zero (e.g. the ground truth against itself): any floor.
            low = max(np.min(positive), 1e-4) if positive.size else 1e-4
            high = max(np.max(all_errors), low * 10)
            bins = np.logspace(math.log10(low), math.log10(high), 40)
            for label, values in errors.items():
                ax.hist(np.maximum(values, low), bins=bins, histtype='step',
                        linewidth=1.8, label=label)
            ax.set_xscale('log')
            ax.set_xlabel('camera centre error (m, log scale)')
            ax.set_ylabel('images')
            ax.legend(fontsize=8)
            ax.grid(alpha=0.3)
            fig.tight_layout()
            body += self.figure(fig, 'pose_error_histogram',
                                'Histogram of camera centre errors')
        self.section('Camera poses', body)

    def trajectory_figure(self, eval_dir):
        path = os.path.join(eval_dir, 'trajectories.csv')
        if not os.path.isfile(path):
            return ''
        columns = {}
        with open(path) as stream:
            for row in csv.DictReader(stream):
                for key, value in row.items():
                    columns.setdefault(key, []).append(
                        float(value) if value not in ('', None) and
                        key != 'frame' else (value if key == 'frame'
                                             else np.nan))
        fig, ax = plt.subplots(figsize=(9, 6))
        styles = [('gt', 'ground truth', 'k-', 2.0),
                  ('prior', 'priors', 'r.', 1.0),
                  ('refined', 'refined (no alignment)', 'b.-', 1.0)]
        for key, label, style, width in styles:
            x = np.array(columns.get(key + '_x', []), dtype=float)
            y = np.array(columns.get(key + '_y', []), dtype=float)
            if len(x) and np.isfinite(x).any():
                ax.plot(x, y, style, label=label, linewidth=width,
                        markersize=5)
        ax.set_aspect('equal', adjustable='datalim')
        ax.set_xlabel('x (m)')
        ax.set_ylabel('y (m)')
        ax.legend()
        ax.grid(alpha=0.3)
        ax.set_title('Camera trajectories from above (world frame)')
        fig.tight_layout()
        return self.figure(fig, 'trajectories', 'Trajectories from above: '
                           'ground truth, priors, refined')

    # ---- Meshes.
    @staticmethod
    def alignment_note(eval_dir):
        data = load_json(os.path.join(eval_dir, 'mesh_alignment.json'))
        if data is None or data['alignment'] == 'none':
            return ' The meshes are compared as reconstructed, unaligned.'
        return (f' The meshes are first carried into the ground-truth frame '
                f'by the {esc(data["alignment"])} alignment of the refined '
                'camera centres (eval/mesh_alignment.json): the world frame '
                'of a reconstruction from noisy priors is only known to the '
                'accuracy of the priors\' mean, which the table would '
                'otherwise measure.')

    def meshes(self):
        eval_dir = os.path.join(self.workspace, 'eval')
        results = []
        for name, label in MESH_METHODS:
            data = load_json(os.path.join(eval_dir, f'mesh_{name}.json'))
            if data is not None:
                results.append((name, label, data))
        if not results:
            self.section('Mesh', '<p>No mesh evaluation: the recording has '
                         'no reference.ply, or the evaluate stage has not '
                         'run.</p>')
            return
        thresholds = results[0][2]['thresholds_m']
        head = ''.join(f'<th>{t:g} m</th>' for t in thresholds)
        rows = []
        for name, label, data in results:
            cells = ''.join(
                f'<td>{p:.3f} / {r:.3f} / <b>{f:.3f}</b></td>'
                for p, r, f in zip(data['precision'], data['recall'],
                                   data['fscore']))
            rows.append(f'<tr><td>{esc(label)}</td>{cells}</tr>')
        body = ('<p>Precision / recall / <b>F-score</b> per distance '
                'threshold against the reference cloud (Knapitsch et al. '
                '2017). Precision: share of mesh samples within the '
                'threshold of the reference; recall: share of the reference '
                'points near what the sensors observed (the registered '
                'LIDAR cloud) within the threshold of the mesh.'
                f'{self.alignment_note(eval_dir)}</p>'
                f'<table><tr><th>method</th>{head}</tr>' + '\n'.join(rows) +
                '</table>')
        fig, axes = plt.subplots(1, 3, figsize=(13, 4))
        for key, title, ax in zip(('precision', 'recall', 'fscore'),
                                  ('precision', 'recall', 'F-score'), axes):
            for name, label, data in results:
                ax.plot(data['thresholds_m'], data[key], 'o-', label=label)
            ax.set_xscale('log')
            ax.set_xlabel('threshold (m)')
            ax.set_title(title)
            ax.set_ylim(0, 1.02)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.tight_layout()
        body += self.figure(fig, 'mesh_precision_recall',
                            'Precision, recall and F-score vs threshold')
        for name, label, data in results:
            body += self.render_mesh(eval_dir, name, label,
                                     data.get('color_threshold_m', 0.1))
        self.section('Mesh', body)

    def render_mesh(self, eval_dir, name, label, color_threshold):
        precision = os.path.join(eval_dir, f'mesh_{name}_precision.ply')
        recall = os.path.join(eval_dir, f'mesh_{name}_recall.ply')
        if not (os.path.isfile(precision) and os.path.isfile(recall)):
            return ''
        fig, axes = plt.subplots(1, 2, figsize=(14, 5.5))
        bounds = splat_view(axes[1], recall,
                            'reference coloured by distance to the mesh '
                            '(recall)')
        splat_view(axes[0], precision,
                   'mesh samples coloured by distance to the reference '
                   '(precision)', bounds)
        fig.suptitle(f'{label}: blue 0 m, red {color_threshold:g} m or more, '
                     'grey not evaluated', fontsize=10)
        fig.tight_layout()
        return self.figure(fig, f'mesh_{name}', f'{label}, coloured by error')

    # ---- Lines.
    def lines(self):
        db_path = os.path.join(self.workspace, 'database.db')
        if not os.path.isfile(db_path):
            return
        connection = sqlite3.connect(f'file:{db_path}?mode=ro', uri=True)
        try:
            tables = {row[0] for row in connection.execute(
                "SELECT name FROM sqlite_master WHERE type='table'")}
            if 'ext_line_segments' not in tables:
                return
            images = connection.execute(
                'SELECT images.image_id, images.name, COUNT(*) FROM images '
                'JOIN ext_line_segments USING (image_id) '
                'GROUP BY images.image_id ORDER BY images.name').fetchall()
            if not images:
                self.section('Lines', '<p>No line segment was extracted.</p>')
                return
            track_of = {}
            if 'ext_line_track_elements' in tables:
                for line_id, image_id, idx in connection.execute(
                        'SELECT line3D_id, image_id, idx FROM '
                        'ext_line_track_elements'):
                    track_of[(image_id, idx)] = line_id
            counts = [count for _, _, count in images]
            body = (f'<p>{sum(counts)} 3D line segments in {len(images)} '
                    f'images ({np.mean(counts):.1f} per image), '
                    f'{len(set(track_of.values()))} line tracks with '
                    f'{len(track_of)} observations. Overlays: each segment '
                    'coloured by its track (the same colour in both images '
                    'is the same 3D line), grey when it joined no track.</p>')
            image_dir = self.image_dir()
            picks = [images[len(images) // 3], images[len(images) // 3 + 1]
                     if len(images) > 1 else images[0]]
            fig, axes = plt.subplots(1, len(picks), figsize=(15, 4.8))
            axes = np.atleast_1d(axes)
            for ax, (image_id, image_name, _) in zip(axes, picks):
                path = os.path.join(image_dir, image_name)
                if os.path.isfile(path):
                    ax.imshow(plt.imread(path), cmap='gray')
                for idx, blob in connection.execute(
                        'SELECT idx, segment2D FROM ext_line_segments WHERE '
                        'image_id = ?', (image_id,)):
                    x1, y1, x2, y2 = struct.unpack('<4d', blob)
                    track = track_of.get((image_id, idx))
                    color = ('0.6' if track is None else
                             plt.cm.tab20((track * 7) % 20))
                    ax.plot([x1 - 0.5, x2 - 0.5], [y1 - 0.5, y2 - 0.5],
                            color=color, linewidth=2.0)
                ax.set_title(image_name, fontsize=9)
                ax.axis('off')
            fig.tight_layout()
            body += self.figure(fig, 'line_overlays',
                                'Line segments of two neighbouring images')
            self.section('Lines', body)
        finally:
            connection.close()

    def image_dir(self):
        path_file = os.path.join(self.workspace, 'pipeline', 'image_path.txt')
        if os.path.isfile(path_file):
            with open(path_file) as stream:
                return stream.read().strip()
        return os.path.join(self.workspace, 'images')

    def write(self):
        self.stages()
        self.poses()
        self.lines()
        self.meshes()
        page = ('<!DOCTYPE html><html><head><meta charset="utf-8">'
                '<title>colmap-lidar report</title><style>'
                'body{font-family:sans-serif;max-width:1400px;margin:2em auto;'
                'padding:0 1em;color:#222}'
                'table{border-collapse:collapse;margin:1em 0}'
                'th,td{border:1px solid #ccc;padding:4px 8px;'
                'text-align:right}td:first-child,th:first-child'
                '{text-align:left}tr.total{font-weight:bold}'
                'figure{margin:1em 0}img{max-width:100%}'
                'figcaption{color:#555;font-size:90%}</style></head><body>'
                '<h1>colmap-lidar reconstruction report</h1>'
                f'<p>Workspace <code>{esc(os.path.abspath(self.workspace))}'
                f'</code>, recording <code>'
                f'{esc(os.path.abspath(self.dataset))}</code>.</p>' +
                '\n'.join(self.sections) + '</body></html>\n')
        path = os.path.join(self.output_dir, 'index.html')
        temp = path + '.tmp'
        with open(temp, 'w') as stream:
            stream.write(page)
        os.replace(temp, path)
        print(f'report: {self.num_figures} figures, {path}')


PLY_TYPES = {'char': 'i1', 'int8': 'i1', 'uchar': 'u1', 'uint8': 'u1',
             'short': 'i2', 'int16': 'i2', 'ushort': 'u2', 'uint16': 'u2',
             'int': 'i4', 'int32': 'i4', 'uint': 'u4', 'uint32': 'u4',
             'float': 'f4', 'float32': 'f4', 'double': 'f8',
             'float64': 'f8'}


# Vertices per chunk: the coloured PLYs of a long recording hold tens of
# millions of samples (35 bytes each); no step holds more than a chunk of
# them, so that the report's memory does not grow with the recording.
CHUNK_VERTICES = 1 << 18


def iter_ply_vertices(path, chunk=CHUNK_VERTICES):
    """The vertex element of a binary little-endian PLY, as structured
    arrays of at most `chunk` vertices (the coloured PLYs of mesh_evaluator
    have vertices only)."""
    with open(path, 'rb') as stream:
        if stream.readline().strip() != b'ply':
            raise ValueError(f'{path}: not a PLY file')
        fields = []
        count = 0
        in_vertex = False
        while True:
            line = stream.readline()
            if not line:
                raise ValueError(f'{path}: no end_header')
            words = line.decode('ascii').split()
            if not words:
                continue
            if words[0] == 'format' and words[1] != 'binary_little_endian':
                raise ValueError(f'{path}: only binary_little_endian PLY')
            if words[0] == 'element':
                in_vertex = words[1] == 'vertex'
                if in_vertex:
                    count = int(words[2])
            elif words[0] == 'property' and in_vertex:
                if words[1] == 'list':
                    raise ValueError(f'{path}: list property in vertices')
                fields.append((words[2], '<' + PLY_TYPES[words[1]]))
            elif words[0] == 'end_header':
                break
        dtype = np.dtype(fields)
        done = 0
        while done < count:
            n = min(chunk, count - done)
            data = stream.read(dtype.itemsize * n)
            if len(data) != dtype.itemsize * n:
                raise ValueError(f'{path}: truncated after {done} vertices')
            yield np.frombuffer(data, dtype=dtype, count=n)
            done += n


def vertex_chunks(source, chunk):
    """`source`'s vertices in chunks: a PLY path (read as it goes) or a
    structured array with x, y, z, red, green, blue (sliced)."""
    if isinstance(source, (str, os.PathLike)):
        yield from iter_ply_vertices(source, chunk)
    else:
        for start in range(0, len(source), chunk):
            yield source[start:start + chunk]


def splat_view(ax, source, title, bounds=None, azimuth_deg=225.0,
               elevation_deg=50.0, width=900, chunk=CHUNK_VERTICES):
    """Orthographic view from above at an angle of coloured vertices (a
    PLY path or a structured array, vertex_chunks), 2x2 splats: for each of
    the four splat offsets in turn, each pixel takes the colour of the
    nearest vertex landing there, and a later offset overwrites an earlier
    one. Read in chunks of vertices; the bounds (when not given) are the
    0.5 and 99.5 percentiles of the view's coordinates, which need them all
    (16 bytes per vertex)."""
    az, el = math.radians(azimuth_deg), math.radians(elevation_deg)
    forward = np.array([math.cos(el) * math.cos(az),
                        math.cos(el) * math.sin(az), math.sin(el)])
    right = np.array([-math.sin(az), math.cos(az), 0.0])
    up = np.cross(forward, right)

    def xyz_of(vertices):
        return np.stack([vertices['x'], vertices['y'], vertices['z']], 1)

    if bounds is None:
        us, vs = [], []
        for vertices in vertex_chunks(source, chunk):
            xyz = xyz_of(vertices)
            us.append(xyz @ right)
            vs.append(xyz @ up)
        u = np.concatenate(us) if us else np.zeros(1)
        v = np.concatenate(vs) if vs else np.zeros(1)
        del us, vs
        bounds = (np.percentile(u, 0.5), np.percentile(u, 99.5),
                  np.percentile(v, 0.5), np.percentile(v, 99.5))
        del u, v
    u0, u1, v0, v1 = bounds
    scale = (width - 1) / max(u1 - u0, 1e-9)
    height = int((v1 - v0) * scale) + 1
    offsets = ((0, 0), (0, 1), (1, 0), (1, 1))
    # Per offset: the nearest vertex's depth and colour per pixel (a larger
    # depth along `forward` is nearer the viewer).
    nearest = np.full((len(offsets), height * width), -np.inf)
    colors = np.zeros((len(offsets), height * width, 3), dtype=np.uint8)
    for vertices in vertex_chunks(source, chunk):
        xyz = xyz_of(vertices)
        rgb = np.stack([vertices['red'], vertices['green'],
                        vertices['blue']], 1)
        # Far first, so that in each assignment below the nearest vertex
        # landing on a pixel is written last and stays.
        depth = xyz @ forward
        order = np.argsort(depth)
        xyz, rgb, depth = xyz[order], rgb[order], depth[order]
        col = np.round((xyz @ right - u0) * scale).astype(np.int64)
        row = np.round((v1 - xyz @ up) * scale).astype(np.int64)
        for k, (dr, dc) in enumerate(offsets):
            r, c = row + dr, col + dc
            ok = np.flatnonzero((r >= 0) & (r < height) & (c >= 0) &
                                (c < width))
            pixel = r[ok] * width + c[ok]
            chunk_nearest = np.full(height * width, -np.inf)
            chunk_nearest[pixel] = depth[ok]
            chunk_vertex = np.zeros(height * width, dtype=np.int64)
            chunk_vertex[pixel] = ok
            nearer = chunk_nearest > nearest[k]
            nearest[k, nearer] = chunk_nearest[nearer]
            colors[k, nearer] = rgb[chunk_vertex[nearer]]
    image = np.full((height * width, 3), 255, dtype=np.uint8)
    for k in range(len(offsets)):
        hit = nearest[k] > -np.inf
        image[hit] = colors[k, hit]
    ax.imshow(image.reshape(height, width, 3))
    ax.set_title(title, fontsize=9)
    ax.axis('off')
    return bounds


def main(argv):
    if len(argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    workspace, dataset, output_dir = argv[1:]
    os.makedirs(output_dir, exist_ok=True)
    Report(workspace, dataset, output_dir).write()
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
