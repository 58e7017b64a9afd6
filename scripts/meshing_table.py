#!/usr/bin/python3
"""Helpers of scripts/bench_meshing_table.sh (numpy + matplotlib).

  meshing_table.py poisson_input IN.ply OUT.ply
      Copies x y z nx ny nz of a binary PLY (e.g. lidar_fused.ply, which also
      has a uint `count` that colmap's PLY reader rejects) into a float PLY
      that `colmap poisson_mesher` reads.
  meshing_table.py poisson_trim MESH.ply OUT.ply QUANTILE
      Drops the faces of a `colmap poisson_mesher --PoissonMeshing.trim 0.001`
      mesh (a tiny trim that keeps the vertex density `value`) whose vertices
      have a density `value` below the given quantile of
      the vertex values (a data-driven trim; the fixed default trim 10 of
      colmap can give an empty mesh, docs colmap-formats.md 4.10).
  meshing_table.py render EST_COLORED.ply REF_COLORED.ply OUT.png TITLE
      Renders the estimate coloured by its distance to the reference
      (precision view) and the reference coloured by its distance to the
      estimate (recall view), as written by `mesh_evaluator`, side by side in
      an oblique orthographic view with a z-buffer.
  meshing_table.py table ROWS.tsv
      Prints the markdown table (precision / recall / F-score per threshold,
      time, peak memory) from rows "label<TAB>report.json<TAB>mesh_s<TAB>
      mesh_MiB<TAB>total_s".
"""
import json
import os
import sys

import numpy as np

PLY_TYPES = {
    'char': 'i1', 'int8': 'i1', 'uchar': 'u1', 'uint8': 'u1',
    'short': 'i2', 'int16': 'i2', 'ushort': 'u2', 'uint16': 'u2',
    'int': 'i4', 'int32': 'i4', 'uint': 'u4', 'uint32': 'u4',
    'float': 'f4', 'float32': 'f4', 'double': 'f8', 'float64': 'f8',
}


def read_ply(path):
    """Returns (vertices structured array, faces int array (n, 3) or None)."""
    with open(path, 'rb') as f:
        header = []
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f'{path}: no end_header')
            line = line.decode('ascii').strip()
            header.append(line)
            if line == 'end_header':
                break
        if 'format binary_little_endian 1.0' not in header:
            raise ValueError(f'{path}: only binary little-endian PLY')
        elements = []  # (name, count, [(prop, dtype)] or list spec)
        for line in header:
            e = line.split()
            if e[0] == 'element':
                elements.append((e[1], int(e[2]), []))
            elif e[0] == 'property':
                if e[1] == 'list':
                    elements[-1][2].append(('list', PLY_TYPES[e[2]],
                                            PLY_TYPES[e[3]], e[4]))
                else:
                    elements[-1][2].append((e[2], PLY_TYPES[e[1]]))
        data = f.read()
    offset = 0
    vertices, faces = None, None
    for name, count, props in elements:
        if any(p[0] == 'list' for p in props):
            # Only triangle faces with a single list property are supported.
            _, count_type, index_type, _ = props[0]
            dtype = np.dtype([('n', '<' + count_type),
                              ('v', '<' + index_type, 3)])
            arr = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            if count and not np.all(arr['n'] == 3):
                raise ValueError(f'{path}: only triangles are supported')
            faces = arr['v'].astype(np.int64)
        else:
            dtype = np.dtype([(p, '<' + t) for p, t in props])
            arr = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            if name == 'vertex':
                vertices = arr
        offset += dtype.itemsize * count
    return vertices, faces


def write_ply(path, vertices, faces=None):
    header = ['ply', 'format binary_little_endian 1.0',
              f'element vertex {len(vertices)}']
    for name in vertices.dtype.names:
        kind = vertices.dtype[name].str[1:]
        ply_type = {'f4': 'float', 'f8': 'double', 'u1': 'uchar',
                    'i4': 'int', 'u4': 'uint'}[kind]
        header.append(f'property {ply_type} {name}')
    if faces is not None:
        header += [f'element face {len(faces)}',
                   'property list uchar int vertex_indices']
    header.append('end_header')
    with open(path, 'wb') as f:
        f.write(('\n'.join(header) + '\n').encode('ascii'))
        f.write(vertices.tobytes())
        if faces is not None:
            rows = np.zeros(len(faces), dtype=[('n', 'u1'), ('v', '<i4', 3)])
            rows['n'] = 3
            rows['v'] = faces
            f.write(rows.tobytes())


def poisson_input(src, dst):
    vertices, _ = read_ply(src)
    names = ['x', 'y', 'z', 'nx', 'ny', 'nz']
    out = np.zeros(len(vertices), dtype=[(n, '<f4') for n in names])
    for n in names:
        out[n] = vertices[n]
    write_ply(dst, out)
    print(f'{len(out)} points with normals -> {dst}')


def poisson_trim(src, dst, quantile):
    vertices, faces = read_ply(src)
    value = vertices['value']
    threshold = np.quantile(value, quantile)
    keep = np.all(value[faces] >= threshold, axis=1)
    faces = faces[keep]
    used = np.unique(faces)
    remap = -np.ones(len(vertices), dtype=np.int64)
    remap[used] = np.arange(len(used))
    out = np.zeros(len(used), dtype=[(n, '<f4') for n in 'xyz'])
    for n in 'xyz':
        out[n] = vertices[n][used]
    write_ply(dst, out, remap[faces])
    print(f'trim at value {threshold:.3f} (quantile {quantile}): '
          f'{len(faces)} faces, {len(used)} vertices -> {dst}')


def render_view(ax, path, title, bounds=None):
    # The report's renderer (src/pipeline/report.py), from a 45-degree view.
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                    '..', 'src', 'pipeline'))
    from report import splat_view
    vertices, _ = read_ply(path)
    return splat_view(ax, vertices, title, bounds=bounds, elevation_deg=45.0)


def render(est_path, ref_path, out_png, title):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(14, 5.5), dpi=100)
    # Both panels share the framing of the reference (the kept surface).
    bounds = render_view(axes[1], ref_path,
                         'reference coloured by distance to the estimate '
                         '(recall view)')
    render_view(axes[0], est_path,
                'estimate coloured by distance to the reference '
                '(precision view)', bounds=bounds)
    fig.suptitle(title + '  (blue: 0 m, red: the colour threshold or more, '
                 'grey: not evaluated)',
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(out_png)
    print(f'wrote {out_png}')


def table(rows_path):
    rows = []
    with open(rows_path) as f:
        for line in f:
            if line.strip():
                rows.append(line.rstrip('\n').split('\t'))
    thresholds = None
    out = []
    for label, report_path, mesh_s, mesh_mib, total_s in rows:
        with open(report_path) as f:
            report = json.load(f)
        if thresholds is None:
            thresholds = report['thresholds_m']
            head = ['method'] + [f'{t:g} m P / R / F' for t in thresholds] + \
                ['faces', 'meshing s', 'meshing peak MiB', 'total s']
            out.append('| ' + ' | '.join(head) + ' |')
            out.append('|' + '---|' * len(head))
        cells = [label]
        for p, r, fs in zip(report['precision'], report['recall'],
                            report['fscore']):
            cells.append(f'{p:.3f} / {r:.3f} / **{fs:.3f}**')
        cells += [str(report['num_estimate_triangles']), mesh_s, mesh_mib,
                  total_s]
        out.append('| ' + ' | '.join(cells) + ' |')
    print('\n'.join(out))


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    command, args = sys.argv[1], sys.argv[2:]
    if command == 'poisson_input' and len(args) == 2:
        poisson_input(*args)
    elif command == 'poisson_trim' and len(args) == 3:
        poisson_trim(args[0], args[1], float(args[2]))
    elif command == 'render' and len(args) == 4:
        render(*args)
    elif command == 'table' and len(args) == 1:
        table(*args)
    else:
        sys.exit(__doc__)


if __name__ == '__main__':
    main()
