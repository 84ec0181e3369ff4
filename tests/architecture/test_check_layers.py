#!/usr/bin/env python3
"""check_layers.py on small trees made here: a clean tree passes, and each kind of broken rule fails with its line."""
import os
import subprocess
import sys
import tempfile

CHECK = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'check_layers.py')


def run(files):
    with tempfile.TemporaryDirectory() as root:
        for path, text in files.items():
            full = os.path.join(root, path)
            os.makedirs(os.path.dirname(full), exist_ok=True)
            with open(full, 'w', encoding='utf-8') as f:
                f.write(text)
        p = subprocess.run([sys.executable, CHECK, root], capture_output=True, text=True)
        return p.returncode, p.stdout


CLEAN = {
    'icobrdf/core/support/error.hpp': '#pragma once\n',
    'icobrdf/core/grid/grid.hpp': '#include "icobrdf/core/support/error.hpp"\n',
    'icobrdf/io/reader.hpp': '#include "icobrdf/core/grid/grid.hpp"\n',
    'icobrdf/pipeline/a.hpp': '#include "icobrdf/io/reader.hpp"\n',
    'icobrdf/pipeline/a.cpp': '#include "icobrdf/pipeline/a.hpp"\n// dynamic_cast in a comment is fine\n',
}


def expect(case, files, code, needle):
    rc, out = run(files)
    if rc != code or needle not in out:
        print(f'FAIL {case}: exit {rc}, expected {code}; output:\n{out}')
        return 1
    return 0


def main():
    bad = 0
    bad += expect('clean tree', CLEAN, 0, '0 rules broken')
    bad += expect('room above', {**CLEAN, 'icobrdf/core/grid/grid.hpp': '#include "icobrdf/core/fit/x.hpp"\n',
                                 'icobrdf/core/fit/x.hpp': '#pragma once\n'}, 1, 'which is above it')
    bad += expect('layer above', {**CLEAN, 'icobrdf/io/reader.hpp': '#include "icobrdf/pipeline/a.hpp"\n'}, 1, 'not below it')
    bad += expect('module cycle', {**CLEAN, 'icobrdf/pipeline/b.hpp': '#include "icobrdf/pipeline/a.hpp"\n',
                                   'icobrdf/pipeline/a.cpp': '#include "icobrdf/pipeline/b.hpp"\n'}, 1, 'depend on each other')
    bad += expect('downcast', {**CLEAN, 'icobrdf/pipeline/a.cpp': 'auto* m = dynamic_cast<const X*>(&s);\n'}, 1, 'never downcasts')
    print(f'{5 - bad} passed, {bad} failed')
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
