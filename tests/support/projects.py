"""Small projects built for tests."""

from __future__ import annotations

import hashlib
import io
import json
import math
import struct
import wave
import zipfile

from scratchworld_dist.sb3 import Project, block, circle_costume, rect_costume


def counter_project(name: str = "Counter", target: int = 10) -> Project:
    """A sprite that counts a global variable up to ``target`` and says the result."""
    project = Project()
    project.stage.variable("count", 0)
    project.sprite(name, costume=circle_costume("dot", 10, "#36c")).script(
        block("event_whenflagclicked"),
        block("data_setvariableto", VARIABLE="count", VALUE=0),
        block("control_repeat", TIMES=target, SUBSTACK=[block("data_changevariableby", VARIABLE="count", VALUE=1)]),
        block("looks_say", MESSAGE="done"),
    )
    return project


def _beep_wav(seconds: float, rate: int = 22050) -> bytes:
    """A quiet 440 Hz tone as 16-bit mono WAV."""
    frames = b"".join(
        struct.pack("<h", int(3000 * math.sin(2 * math.pi * 440 * i / rate))) for i in range(int(seconds * rate))
    )
    buffer = io.BytesIO()
    with wave.open(buffer, "wb") as out:
        out.setnchannels(1)
        out.setsampwidth(2)
        out.setframerate(rate)
        out.writeframes(frames)
    return buffer.getvalue()


def with_sound(sb3: bytes, sprite: str, name: str, seconds: float) -> bytes:
    """The project with a WAV sound added to ``sprite`` (the builder makes costumes only)."""
    wav = _beep_wav(seconds)
    asset_id = hashlib.md5(wav).hexdigest()  # Scratch names assets by their MD5
    with zipfile.ZipFile(io.BytesIO(sb3)) as archive:
        files = {info.filename: archive.read(info) for info in archive.infolist()}
    project = json.loads(files["project.json"])
    target = next(t for t in project["targets"] if t["name"] == sprite)
    target["sounds"].append(
        {
            "name": name,
            "assetId": asset_id,
            "dataFormat": "wav",
            "format": "",
            "rate": 22050,
            "sampleCount": int(seconds * 22050),
            "md5ext": f"{asset_id}.wav",
        }
    )
    files["project.json"] = json.dumps(project).encode()
    files[f"{asset_id}.wav"] = wav
    buffer = io.BytesIO()
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        for filename, data in sorted(files.items()):
            archive.writestr(filename, data)
    return buffer.getvalue()


SOUND_SECONDS = 0.6


def timing_project() -> bytes:
    """Scripts started by broadcasts, one per timing-sensitive behaviour (see tests/data/clock_behaviours.js)."""
    project = Project()
    project.stage.variable("inner_done", 0)
    project.stage.variable("clones", 0)
    project.stage.variable("seen", 0)
    walker = project.sprite("Walker", costume=circle_costume("dot", 10, "#36c"), x=-200, y=120)
    walker.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="wait"),
        block("control_wait", DURATION=0.5),
        block("looks_say", MESSAGE="waited"),
    )
    walker.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="glide"),
        block("motion_gotoxy", X=-100, Y=120),
        block("motion_glidesecstoxy", SECS=1, X=100, Y=120),
        block("looks_say", MESSAGE="glided"),
    )
    walker.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="ask"),
        block("sensing_askandwait", QUESTION="name?"),
        block("looks_say", MESSAGE=block("operator_join", STRING1="hi ", STRING2=block("sensing_answer"))),
    )
    walker.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="chain"),
        block("event_broadcastandwait", BROADCAST_INPUT="inner"),
        block("looks_say", MESSAGE="after inner"),
    )
    walker.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="inner"),
        block("control_wait", DURATION=0.3),
        block("data_changevariableby", VARIABLE="inner_done", VALUE=1),
    )
    walker.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="clone"),
        block(
            "control_repeat",
            TIMES=3,
            SUBSTACK=[block("control_create_clone_of", CLONE_OPTION="_myself_"), block("control_wait", DURATION=0.1)],
        ),
    )
    walker.script(
        block("control_start_as_clone"),
        block("data_changevariableby", VARIABLE="clones", VALUE=1),
        block("control_wait", DURATION=0.5),
        block("control_delete_this_clone"),
    )
    mover = project.sprite("Mover", costume=circle_costume("ball", 10, "#e33"), x=-150, y=0)
    mover.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="touch"),
        block("motion_gotoxy", X=-150, Y=0),
        block(
            "control_repeat_until",
            CONDITION=block("sensing_touchingobject", TOUCHINGOBJECTMENU="Wall"),
            SUBSTACK=[block("motion_changexby", DX=5)],
        ),
        block("looks_say", MESSAGE="touched"),
    )
    # A loop that never redraws: the VM spins in it until the frame's work budget runs out.
    mover.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="touch"),
        block(
            "control_forever",
            SUBSTACK=[
                block(
                    "control_if",
                    CONDITION=block("sensing_touchingobject", TOUCHINGOBJECTMENU="Wall"),
                    SUBSTACK=[block("data_setvariableto", VARIABLE="seen", VALUE=1)],
                )
            ],
        ),
    )
    project.sprite("Wall", costume=rect_costume("wall", 20, 200, "#333"), x=100, y=0)
    speaker = project.sprite("Speaker", costume=circle_costume("spk", 10, "#3a3"), x=200, y=-120)
    speaker.script(
        block("event_whenbroadcastreceived", BROADCAST_OPTION="sound"),
        block("sound_playuntildone", SOUND_MENU="beep"),
        block("looks_say", MESSAGE="sound done"),
    )
    return with_sound(project.to_sb3(), "Speaker", "beep", SOUND_SECONDS)


def with_entry(sb3: bytes, name: str, data: bytes, level: int = 1) -> bytes:
    """The archive with one more entry (deflated), e.g. an asset that inflates to gigabytes."""
    buffer = io.BytesIO(sb3)
    with zipfile.ZipFile(buffer, "a", zipfile.ZIP_DEFLATED, compresslevel=level) as archive:
        archive.writestr(name, data)
    return buffer.getvalue()


def with_declared_size(sb3: bytes, name: str, size: int) -> bytes:
    """The archive with ``name``'s size as declared in its headers replaced by ``size`` (a lie)."""
    info = zipfile.ZipFile(io.BytesIO(sb3)).getinfo(name)
    data = bytearray(sb3)
    struct.pack_into("<L", data, info.header_offset + 22, size)  # local header: uncompressed size
    position = 0
    while (position := sb3.find(b"PK\x01\x02", position)) >= 0:  # central directory entries
        length = struct.unpack_from("<H", sb3, position + 28)[0]
        if sb3[position + 46 : position + 46 + length] == name.encode():
            struct.pack_into("<L", data, position + 24, size)
        position += 4
    return bytes(data)
