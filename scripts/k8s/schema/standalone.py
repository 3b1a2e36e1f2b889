#!/usr/bin/env python3
"""Makes the self-contained schemas of this folder from kubernetes-validate's "local-strict" ones.

kubernetes-validate (PyPI, Apache-2.0) ships one JSON schema per kind that refers to a shared
/api/_definitions.json (1.8 MB). This script copies a kind's schema and inlines, under $defs,
exactly the definitions it reaches, so the result validates offline with no reference resolver.

    pip download --no-deps kubernetes-validate==1.37.0 -d /tmp/kv
    cd /tmp/kv && python3 -m zipfile -e kubernetes_validate-1.37.0-py3-none-any.whl .
    python3 standalone.py /tmp/kv/kubernetes_validate/kubernetes-json-schema/v1.37.0-local-strict \
        job-batch-v1 persistentvolumeclaim-v1
"""

import json
import re
import sys
from pathlib import Path

REF = re.compile(r'"#/\$defs/([^"]+)"')
SHARED = "/api/_definitions.json#/$defs/"


def main() -> None:
    source = Path(sys.argv[1])
    definitions = json.loads((source / "_definitions.json").read_text())["$defs"]
    for name in sys.argv[2:]:
        text = (source / f"{name}.json").read_text().replace(SHARED, "#/$defs/")
        schema = json.loads(text)
        reached, todo = set(), REF.findall(text)
        while todo:
            key = todo.pop()
            if key not in reached:
                reached.add(key)
                todo += REF.findall(json.dumps(definitions[key]))
        schema["$defs"] = {key: definitions[key] for key in sorted(reached)}
        out = Path(__file__).parent / f"{name}.json"
        out.write_text(json.dumps(schema, indent=1, sort_keys=True) + "\n")
        print(f"{out}: {len(reached)} definitions")


if __name__ == "__main__":
    main()
