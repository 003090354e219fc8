"""An offline rehearsal of a model run: the whole model path of ``pare run``, with no key and no network.

    python examples/offline_rehearsal.py [--output runs/rehearsal] [--split smoke] [--runs 1]

A local OpenAI-compatible server (``pare.testing.ChatServer`` on 127.0.0.1) plays every role: the user,
the assistant's observe and execute modes (``proactive_play``: the user waits, then accepts the one
proposal; the assistant proposes once, then reports) and the judge (always NO). The script first prints
``pare run --dry-run`` for that configuration (roles, keys, episodes, estimate), then runs it: prompts
rendered, requests sent, answers parsed, the record/replay cache, the run folder, the report. The
rehearsal's models do nothing useful, so the episodes are expected to fail their goals: what it shows is
that everything between PARE and a model works, before a real model (and its bill) is involved.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import Any

from pare.agents.judge import JUDGE_PROMPT
from pare.cli import main as pare
from pare.testing import ChatServer, Reply, Responder, completion, proactive_play


def rehearsal_responder() -> Responder:
    """``proactive_play`` for the user and the assistant, and a judge that answers NO."""
    play = proactive_play()

    def respond(body: dict[str, Any]) -> Reply:
        messages = body.get("messages") or []
        if messages and messages[0].get("content") == JUDGE_PROMPT:
            return completion("NO", prompt_tokens=200, completion_tokens=1, model="rehearsal-judge")
        return play(body)

    return respond


def rehearse(output: str, *, split: str = "smoke", runs: int = 1) -> int:
    """Print the dry run, then run ``split`` ``runs`` times against the local server; the run's exit code."""
    with ChatServer(rehearsal_responder()) as server:
        argv = ["run", "--split", split, "--runs", str(runs), "--output", output, "--no-progress"]
        for role in ("user", "assistant", "judge"):
            argv += [f"--{role}-model", f"rehearsal-{role}", f"--{role}-endpoint", server.base_url]
            argv += ["--set", f"models.{role}.api_key_env=null"]  # a local server: no key
            argv += ["--set", f"models.{role}.prices={{input: 0.0, output: 0.0}}"]  # and no bill
        dry = pare([*argv, "--dry-run"])
        if dry != 0 or server.request_count != 0:
            print(f"the dry run failed ({dry}) or called the server ({server.request_count} requests)")
            return 2
        code = pare(argv)
        print(f"the local server answered {server.request_count} model calls")
        return code


def main(argv: Sequence[str] | None = None) -> int:
    """The command line: where to write the run, which split, how many runs."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--output", default="runs/rehearsal", help="The run folder (default runs/rehearsal).")
    parser.add_argument("--split", default="smoke", help="A split of the library (default smoke).")
    parser.add_argument("--runs", type=int, default=1, help="Runs per scenario (default 1).")
    args = parser.parse_args(argv)
    return rehearse(args.output, split=args.split, runs=args.runs)


if __name__ == "__main__":
    sys.exit(main())
