"""The writer of a run's finished episodes: a small process beside ``pare run``.

:class:`pare.bench.store.RunStore` starts it as ``python -I -S _store_writer.py RUN`` (this module imports
only the standard library, so it starts in milliseconds) and sends it every finished episode. The run plays
its next episode while this process creates the files: creating a file can cost the kernel a millisecond
(ext4 steps over the inodes of files deleted in the last minutes, and runs come and go), as long as a
short episode takes to play. A thread of the run's own process would not do: each of its system calls
hands the GIL back and must then wait to take it again from the thread playing the episodes; on a loaded
machine those waits cost the run as much as the files did.

The protocol. Stdin carries one frame per episode: a header of three little-endian 32-bit lengths (the
trajectory's path relative to RUN, empty when the episode has no trajectory; the trajectory file's bytes;
the record's line), then those bytes. For each frame the trajectory is written to a temporary file and
renamed into place, then the line is appended to ``RUN/episodes.jsonl`` and handed to the OS (the line is
the commit point: it always names a whole trajectory), then one byte ``.`` goes to stdout: the episode is
stored. On an error, ``!`` and a line ``errno<TAB>message<TAB>filename`` go to stdout and the writer stops.
At the end of stdin (the run ended, or its process died) the episodes file is forced to the disk and the
process exits; a frame cut short is dropped (its episode was never reported as stored, so a resume plays
it again).
"""

from __future__ import annotations

# Only modules that are cheap to import (no typing, no contextlib): the process starts with every run.
import os
import struct
import sys
import time
from io import BufferedIOBase, BufferedReader, FileIO, RawIOBase

EPISODES = "episodes.jsonl"
SYNC_INTERVAL_S = 1.0
"""At most this long between forcing the episodes file to the disk (it is handed to the OS at once)."""
HEADER = struct.Struct("<III")
STORED = b"."
FAILED = b"!"


def frame(trajectory_path: str | None, trajectory: bytes, line: bytes) -> bytes:
    """One episode as the writer reads it (``trajectory_path`` relative to the run folder)."""
    path = (trajectory_path or "").encode("utf-8")
    return HEADER.pack(len(path), len(trajectory), len(line)) + path + trajectory + line


def write_atomically(path: str, data: bytes, made: set[str] | None = None) -> None:
    """Write ``data`` to a temporary file beside ``path``, then rename it: ``path`` is whole or absent.
    ``made`` holds folders already made or found (writing the next file beside them skips mkdir).
    """
    folder = os.path.dirname(path)
    if made is None or folder not in made:
        os.makedirs(folder, exist_ok=True)
        if made is not None:
            made.add(folder)
    temporary = path + ".tmp"
    try:
        _write_file(temporary, data)
    except FileNotFoundError:  # the folder went away since it was made
        os.makedirs(folder, exist_ok=True)
        _write_file(temporary, data)
    os.replace(temporary, path)


def _write_file(path: str, data: bytes) -> None:
    handle = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC | getattr(os, "O_BINARY", 0), 0o666)
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(handle, view) :]
    finally:
        os.close(handle)


class EpisodesFile:
    """The run's episodes file, appended to line by line and forced to the disk now and then."""

    def __init__(self, run: str) -> None:
        self._file = open(os.path.join(run, EPISODES), "ab")  # noqa: SIM115 - closed by close()
        self._synced_at = float("-inf")

    def append(self, line: bytes) -> None:
        """Append ``line`` and hand it to the OS at once: a killed run loses nothing it recorded. Forcing
        it to the disk costs milliseconds, so that is done at most once per SYNC_INTERVAL_S and on close:
        a power cut loses at most that window, which a resume plays again.
        """
        self._file.write(line)
        self._file.flush()
        now = time.monotonic()
        if now - self._synced_at >= SYNC_INTERVAL_S:
            os.fsync(self._file.fileno())
            self._synced_at = now

    def close(self) -> None:
        """Force the file to the disk and close it."""
        try:
            self._file.flush()
            os.fsync(self._file.fileno())
        finally:
            self._file.close()


def store(
    run: str, trajectory_path: str, trajectory: bytes, line: bytes, episodes: EpisodesFile, made: set[str]
) -> None:
    """Store one episode: its trajectory (if any), then its line (``made``: see :func:`write_atomically`)."""
    if trajectory_path:
        write_atomically(os.path.join(run, trajectory_path), trajectory, made)
    episodes.append(line)


def describe(error: BaseException) -> bytes:
    """The error reply: ``errno<TAB>message<TAB>filename`` and a newline (errno 0 when not an OSError)."""
    if isinstance(error, OSError):
        fields = [str(error.errno or 0), error.strerror or str(error), str(error.filename or "")]
    else:
        fields = ["0", f"{type(error).__name__}: {error}", ""]
    return "\t".join(" ".join(field.split()) for field in fields).encode("utf-8", "replace") + b"\n"


def _read_frame(source: BufferedIOBase) -> tuple[str, bytes, bytes] | None:
    header = source.read(HEADER.size)
    if len(header) < HEADER.size:
        return None
    sizes = HEADER.unpack(header)
    body = source.read(sum(sizes))
    if len(body) < sum(sizes):
        return None  # cut short: the run died while sending it
    path_end, trajectory_end = sizes[0], sizes[0] + sizes[1]
    return body[:path_end].decode("utf-8"), body[path_end:trajectory_end], body[trajectory_end:]


def serve(run: str, source: BufferedIOBase, replies: BufferedIOBase | RawIOBase) -> int:
    """Store the episodes framed on ``source`` into the run folder ``run``, replying on ``replies``;
    returns the exit status (1 after an error).
    """
    episodes = EpisodesFile(run)
    made: set[str] = set()
    try:
        while (item := _read_frame(source)) is not None:
            store(run, *item, episodes, made)
            replies.write(STORED)
            replies.flush()
    except BrokenPipeError:  # the run is gone: nobody to tell (what it never heard of, it plays again)
        return 0
    except Exception as error:  # told to the run, which raises it
        try:  # contextlib is not imported here
            replies.write(FAILED + describe(error))
            replies.flush()
        except OSError:
            pass  # the run is gone
        return 1
    finally:
        try:  # noqa: SIM105 - contextlib is not imported here
            episodes.close()
        except OSError:
            pass  # what could not be forced to the disk, a resume plays again
    return 0


if __name__ == "__main__":
    frames = BufferedReader(FileIO(sys.stdin.fileno(), closefd=False), buffer_size=1 << 16)
    sys.exit(serve(sys.argv[1], frames, FileIO(sys.stdout.fileno(), "wb", closefd=False)))
