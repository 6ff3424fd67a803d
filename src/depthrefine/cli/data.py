"""``depthrefine data``: the benchmark data sets (sources, licences, checksums); ``data verify``, ``data fetch``."""

from __future__ import annotations

import argparse
import sys


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "data",
        help="list the benchmark data sets (source, licence, files, SHA-256); verify a folder; fetch one",
        description=(
            "Without a subcommand: every data set the benchmark protocols read, and the real captures, with its "
            "original public source, licence, protocols, expected files and whether `data fetch` downloads it. "
            "`data verify DIR` checks a folder laid out as shared/data (or one data set's folder) file by file "
            "against the SHA-256 list; `data fetch NAME --to DIR` downloads a data set whose licence allows it "
            "from its original repository into DIR/<its folder>, checking every file."
        ),
    )
    p.set_defaults(func=run_list, names=[], files=False, sources=False)
    actions = p.add_subparsers(dest="action", metavar="ACTION")
    listing = actions.add_parser("list", help="the data sets (the default)")
    listing.add_argument("names", nargs="*", metavar="NAME", help="only these data sets")
    listing.add_argument("--files", action="store_true", help="also every expected file with its SHA-256 "
                                                              "(sha256sum format)")
    listing.add_argument("--sources", action="store_true",
                         help="also every expected file with the URL it was copied from (or how it was made): "
                              "what to download by hand where `data fetch` refuses")
    listing.set_defaults(func=run_list)
    verify = actions.add_parser("verify", help="check a data folder file by file against the SHA-256 list",
                                description="One line per missing, extra or changed file; exit status 2 on any.")
    verify.add_argument("folder", metavar="DIR", help="a folder laid out as shared/data, or one data set's folder")
    verify.add_argument("names", nargs="*", metavar="NAME",
                        help="data sets that must be in DIR (default: check every data set found there)")
    verify.set_defaults(func=run_verify)
    fetch = actions.add_parser(
        "fetch", help="download a data set from its original source (where its licence allows)",
        description="Download NAME into DIR/<its folder> (e.g. DIR/real_tof/azure_kinect_mug), check every "
                    "file's SHA-256 and only then move the folder into place; a failure leaves nothing behind. "
                    "Data sets without a licence that allows copying are refused, with the reason and the source "
                    "to get them from by hand.")
    fetch.add_argument("name", metavar="NAME", help="the data set (`depthrefine data` lists them)")
    fetch.add_argument("--to", required=True, metavar="DIR", help="the data root to put it in (created if missing)")
    fetch.add_argument("--from", dest="base_url", metavar="URL",
                       help="download from this mirror of raw.githubusercontent.com (URL/OWNER/REPO/COMMIT/PATH; "
                            "default: $DEPTHREFINE_DATA_URL, else https://raw.githubusercontent.com)")
    fetch.add_argument("--overwrite", action="store_true", help="replace the files of an existing data set folder")
    fetch.set_defaults(func=run_fetch)


def run_list(args: argparse.Namespace) -> int:
    from ..io import DATASETS, get_dataset

    datasets = [get_dataset(n) for n in args.names] if args.names else list(DATASETS.values())
    for d in datasets:
        checksums = d.checksums
        print(f"{d.name}  ({d.folder}/, {len(checksums)} files)")
        print(f"  {d.title}")
        print(f"  protocols: {', '.join(d.protocols) or 'none (not scored by bench)'}")
        print(f"  source:    {d.original}")
        print(f"  licence:   {d.licence}")
        fetch = f"refused: {d.fetch_refused}" if d.fetch_refused else f"depthrefine data fetch {d.name} --to DIR"
        if d.fetch_refused and d.sourced:
            fetch += f"; by hand: depthrefine data list {d.name} --sources gives each file's URL"
        print(f"  fetch:     {fetch}")
        if args.files:
            for path, digest in checksums.items():
                print(f"  {digest}  {path}")
        if args.sources:
            urls = d.file_urls()
            for path in checksums:
                how = d.derived.get(path) or "not a copy of a public file: see source"
                print(f"  {path}  {urls.get(path) or f'({how})'}")
        print()
    print("Check a copy: depthrefine data verify DIR (DIR laid out as shared/data); run the table: depthrefine bench "
          "--data DIR --report OUT.")
    return 0


def run_verify(args: argparse.Namespace) -> int:
    from ..io import verify_data

    datasets, problems = verify_data(args.folder, tuple(args.names))
    for problem in problems:
        print(problem)
    count = sum(len(d.checksums) for d in datasets)
    names = ", ".join(d.name for d in datasets)
    if problems:
        print(f"depthrefine data verify: {len(problems)} problem(s) in {args.folder} ({names})", file=sys.stderr)
        return 2
    print(f"ok: {count} files of {len(datasets)} data set(s) match ({names})", file=sys.stderr)
    return 0


def run_fetch(args: argparse.Namespace) -> int:
    from ..io import fetch_dataset, get_dataset

    dataset = get_dataset(args.name)
    folder = fetch_dataset(args.name, args.to, base_url=args.base_url, overwrite=args.overwrite,
                           progress=lambda url: print(f"downloading {url}", file=sys.stderr))
    print(f"wrote {folder} ({len(dataset.checksums)} files, SHA-256 checked; licence: {dataset.licence})",
          file=sys.stderr)
    return 0
