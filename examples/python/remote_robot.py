#!/usr/bin/env python3
"""A remote robot for `avs serve`: plain Python 3, standard library only.

The protocol loop (docs/SERVICE.md, "The remote-robot protocol"):

1. ``POST /v1/sessions {"robot": "remote", "start", "camera"}`` creates a session whose
   robot is this client; ``POST /v1/sessions/{id}/goals {"class": ...}`` starts a search.
2. ``GET /v1/sessions/{id}/robot/next?timeout_ms=...`` long-polls for what the agent asks
   of its robot: 200 ``{"request_id", "kind", "args"}``, or 204 when nothing is pending
   (then the goal's state is checked, and the loop ends once it is no longer queued or
   running).
3. Each request is done on the robot and answered with
   ``POST /v1/sessions/{id}/robot/{request_id}`` and ``{"result": {...}}`` or
   ``{"failure": {"reason", "message"}}``.

At the end one line of JSON is printed; the exit status is 0 when the object was found, 3
when the search ended without it, 1 on an error.

To drive a real robot, replace the methods of ``ToyRobot`` (``move_to``, ``map_update``,
``process_view_cone``) with calls to your robot's drivers and keep the rest. With ROS 2:
``move_to`` is a Nav2 ``NavigateToPose`` goal (answer ``unreachable`` when the planner finds
no path, ``execution_failed`` when it aborts); the ``grid`` of ``map_update`` is a
``nav_msgs/OccupancyGrid`` without its header, so fill ``info`` (``resolution``, ``width``,
``height``, ``origin``) and ``data`` by field copy from the latest ``/map`` message (the
origin must not be rotated); ``process_view_cone`` points the pan-tilt unit, grabs an image,
runs the detector and reports each object's position in the map frame (z above the floor).
Send the real camera in ``CAMERA`` and the real start pose in the session body.

    python3 examples/python/remote_robot.py [--server http://127.0.0.1:7878] [--token T]
                                            [--goal cerealbox] [--timeout-s 600]
    python3 examples/python/remote_robot.py --self-test
"""

from __future__ import annotations

import argparse
import json
import math
import os
import socket
import sys
import time
import urllib.error
import urllib.request
from dataclasses import dataclass
from typing import Any, Callable, Optional

# --------------------------------------------------------------------------------------------
# The robot: a simulated room. Replace these methods with your robot's drivers.
# --------------------------------------------------------------------------------------------

#: The camera as the environment file writes it (avs_format::environment::Camera): degrees,
#: metres. Zoom z divides both fields of view by z.
CAMERA: dict[str, Any] = {
    "hfov_deg": 60.0,
    "vfov_deg": 45.0,
    "pan_deg": [-180.0, 180.0],
    "tilt_deg": [-45.0, 30.0],
    "max_zoom": 4.0,
    "height": 1.2,
}

#: Where the robot stands when the session starts: metres, radians.
START: dict[str, float] = {"x": 1.0, "y": 1.0, "yaw": 0.0}


@dataclass(frozen=True)
class Pose:
    """A planar pose: metres, radians counter-clockwise from +x."""

    x: float
    y: float
    yaw: float

    def to_json(self) -> dict[str, float]:
        return {"x": self.x, "y": self.y, "yaw": self.yaw}


@dataclass(frozen=True)
class Cone:
    """A view cone: the pose to look from, pan (relative to the heading), tilt (negative
    looks down), both radians, and the zoom factor (>= 1)."""

    pose: Pose
    pan: float
    tilt: float
    zoom: float


@dataclass(frozen=True)
class Box:
    """An axis-aligned rectangle on the floor, metres."""

    x0: float
    y0: float
    x1: float
    y1: float

    def contains(self, x: float, y: float, margin: float = 0.0) -> bool:
        return (self.x0 - margin <= x <= self.x1 + margin
                and self.y0 - margin <= y <= self.y1 + margin)

    def centre(self) -> tuple[float, float]:
        return ((self.x0 + self.x1) / 2.0, (self.y0 + self.y1) / 2.0)


class RobotFailure(Exception):
    """An action that did not work: `reason` is one of unreachable, execution_failed,
    invalid_request, unsupported."""

    def __init__(self, reason: str, message: str) -> None:
        super().__init__(f"{reason}: {message}")
        self.reason = reason
        self.message = message


def wrap_angle(a: float) -> float:
    """`a` in (-pi, pi]."""
    return math.atan2(math.sin(a), math.cos(a))


class ToyRobot:
    """A robot in a 6 m x 5 m room (x in [0, 6], y in [0, 5]) with a table and a cereal box
    on it; it moves by teleporting and sees with an ideal detector.

    Replace these methods with your robot's drivers: each takes the request's arguments and
    returns the request's result as a JSON-ready dict, or raises RobotFailure.
    """

    RESOLUTION = 0.1  # metres per grid cell
    ROOM = Box(0.0, 0.0, 6.0, 5.0)
    TABLE = Box(3.4, 2.6, 4.6, 3.4)  # 1.2 m x 0.8 m
    TABLE_HEIGHT = 0.75
    CEREALBOX = (4.1, 3.1, TABLE_HEIGHT + 0.1)  # on the table top
    RADIUS = 0.2  # robot radius: how close the robot's centre may come to an obstacle
    OBJECT_RANGE = (0.5, 3.0)  # metres at zoom 1; the far limit grows with the zoom
    LANDMARK_RANGE = (0.5, 6.0)

    def __init__(self, start: Pose = Pose(**START), camera: Optional[dict[str, Any]] = None):
        self.pose = start
        self.camera = dict(camera or CAMERA)
        self.map_sent = False

    # -- motion ------------------------------------------------------------------------------

    def move_to(self, goal: Pose) -> dict[str, Any]:
        """Go to `goal` (here: teleport); `travelled` is the straight-line distance."""
        self.check_reachable(goal)
        travelled = math.hypot(goal.x - self.pose.x, goal.y - self.pose.y)
        self.pose = goal
        return {"pose": self.pose.to_json(), "travelled": travelled}

    def check_reachable(self, goal: Pose) -> None:
        inside = (self.ROOM.x0 + self.RADIUS <= goal.x <= self.ROOM.x1 - self.RADIUS
                  and self.ROOM.y0 + self.RADIUS <= goal.y <= self.ROOM.y1 - self.RADIUS)
        if not inside:
            raise RobotFailure("unreachable",
                               f"({goal.x:.2f}, {goal.y:.2f}) is outside the room "
                               f"(or within {self.RADIUS} m of a wall)")
        if self.TABLE.contains(goal.x, goal.y, margin=self.RADIUS):
            raise RobotFailure("unreachable",
                               f"({goal.x:.2f}, {goal.y:.2f}) is inside the table "
                               f"(with the robot's {self.RADIUS} m radius)")

    # -- mapping -----------------------------------------------------------------------------

    def map_update(self) -> dict[str, Any]:
        """The room as a nav_msgs/OccupancyGrid without header: the room's cells free, a
        one-cell wall ring around it and the table occupied; everything known."""
        grid = self.occupancy_grid()
        known = sum(1 for v in grid["data"] if v >= 0)
        newly_known = 0 if self.map_sent else known
        self.map_sent = True
        return {"grid": grid, "newly_known": newly_known, "doors": []}

    def occupancy_grid(self) -> dict[str, Any]:
        res = self.RESOLUTION
        cols = round((self.ROOM.x1 - self.ROOM.x0) / res)  # room cells, without the wall ring
        rows = round((self.ROOM.y1 - self.ROOM.y0) / res)
        width, height = cols + 2, rows + 2
        origin = (self.ROOM.x0 - res, self.ROOM.y0 - res)
        data = []
        for row in range(height):  # row 0 at the bottom (smallest y)
            for col in range(width):
                wall = row in (0, height - 1) or col in (0, width - 1)
                cx = origin[0] + (col + 0.5) * res
                cy = origin[1] + (row + 0.5) * res
                data.append(100 if wall or self.TABLE.contains(cx, cy) else 0)
        return {
            "info": {
                "resolution": res,
                "width": width,
                "height": height,
                "origin": {
                    "position": {"x": origin[0], "y": origin[1], "z": 0.0},
                    "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
                },
            },
            "data": data,
        }

    # -- seeing ------------------------------------------------------------------------------

    def process_view_cone(self, cone: Cone, classes: list[str]) -> dict[str, Any]:
        """Move to the cone's pose, point the camera, detect the asked classes."""
        self.check_cone(cone)
        moved = self.move_to(cone.pose)
        detections = []
        if "cerealbox" in classes and self.in_view(cone, self.CEREALBOX, self.OBJECT_RANGE):
            detections.append(self.detection("cerealbox", self.CEREALBOX, 0.8))
        table = (*self.TABLE.centre(), self.TABLE_HEIGHT)
        if "table" in classes and self.in_view(cone, table, self.LANDMARK_RANGE):
            detections.append(self.detection("table", table, 0.9))
        return {"pose": moved["pose"], "detections": detections, "travelled": moved["travelled"]}

    def check_cone(self, cone: Cone) -> None:
        """Refuse pan, tilt or zoom outside the camera's limits (as avs-robot's ViewCone::check)."""
        eps = 1e-9
        pan0, pan1 = (math.radians(v) for v in self.camera["pan_deg"])
        tilt0, tilt1 = (math.radians(v) for v in self.camera["tilt_deg"])
        if not pan0 - eps <= cone.pan <= pan1 + eps:
            raise RobotFailure("invalid_request", f"pan {cone.pan} rad outside [{pan0}, {pan1}]")
        if not tilt0 - eps <= cone.tilt <= tilt1 + eps:
            raise RobotFailure("invalid_request",
                               f"tilt {cone.tilt} rad outside [{tilt0}, {tilt1}]")
        if not 1.0 <= cone.zoom <= self.camera["max_zoom"] + eps:
            raise RobotFailure("invalid_request",
                               f"zoom {cone.zoom} outside [1, {self.camera['max_zoom']}]")

    def in_view(self, cone: Cone, point: tuple[float, float, float],
                range_m: tuple[float, float]) -> bool:
        """Whether `point` is within range (far limit x zoom) and inside the image."""
        dx, dy = point[0] - cone.pose.x, point[1] - cone.pose.y
        distance = math.hypot(dx, dy)
        if not range_m[0] <= distance <= range_m[1] * cone.zoom:
            return False
        bearing = wrap_angle(math.atan2(dy, dx) - (cone.pose.yaw + cone.pan))
        elevation = math.atan2(point[2] - self.camera["height"], distance) - cone.tilt
        half_h = math.radians(self.camera["hfov_deg"]) / 2.0 / cone.zoom
        half_v = math.radians(self.camera["vfov_deg"]) / 2.0 / cone.zoom
        return abs(bearing) <= half_h and abs(elevation) <= half_v

    @staticmethod
    def detection(cls: str, point: tuple[float, float, float], confidence: float) -> dict:
        return {"class": cls,
                "pose": {"x": point[0], "y": point[1], "z": point[2]},
                "confidence": confidence}


# --------------------------------------------------------------------------------------------
# Requests → robot calls. Kinds not listed here (classify_place, detector_scores, attention,
# recognise, anything new) are answered `unsupported`.
# --------------------------------------------------------------------------------------------


def parse_pose(v: Any) -> Pose:
    return Pose(float(v["x"]), float(v["y"]), float(v["yaw"]))


def parse_cone(v: Any) -> Cone:
    return Cone(parse_pose(v["pose"]), float(v["pan"]), float(v["tilt"]), float(v["zoom"]))


HANDLERS: dict[str, Callable[[ToyRobot, dict], dict]] = {
    "move_to": lambda robot, args: robot.move_to(parse_pose(args["goal"])),
    "map_update": lambda robot, args: robot.map_update(),
    "process_view_cone": lambda robot, args: robot.process_view_cone(
        parse_cone(args["cone"]), [str(c) for c in args["classes"]]),
}


def answer(robot: ToyRobot, kind: str, args: Any) -> dict[str, Any]:
    """The body answering one request: {"result": ...} or {"failure": ...}."""
    handler = HANDLERS.get(kind)
    if handler is None:
        return failure("unsupported", f"this robot does not do {kind!r}")
    try:
        return {"result": handler(robot, args if isinstance(args, dict) else {})}
    except RobotFailure as e:
        return failure(e.reason, e.message)
    except (KeyError, TypeError, ValueError) as e:
        return failure("invalid_request", f"{kind}: bad arguments ({type(e).__name__}: {e})")


def failure(reason: str, message: str) -> dict[str, Any]:
    return {"failure": {"reason": reason, "message": message}}


# --------------------------------------------------------------------------------------------
# HTTP
# --------------------------------------------------------------------------------------------


class ServiceError(Exception):
    """The server refused a call or could not be reached."""


class PollTimeout(Exception):
    """A long poll ran out of time on the client side: not an error, poll again."""


class GoalTimeout(Exception):
    """The goal did not end within --timeout-s; `status` is its last known status."""

    def __init__(self, status: dict[str, Any]) -> None:
        super().__init__("timed out")
        self.status = status


class Client:
    """JSON over HTTP to `avs serve`, with an optional bearer token."""

    def __init__(self, server: str, token: Optional[str]) -> None:
        self.server = server.rstrip("/")
        self.token = token

    def call(self, method: str, path: str, body: Any = None,
             timeout: float = 30.0) -> tuple[int, Any]:
        """(status, parsed JSON body or None). Raises ServiceError on an HTTP error status or
        when the server cannot be reached, PollTimeout when the socket times out."""
        data = None if body is None else json.dumps(body).encode()
        req = urllib.request.Request(self.server + path, data=data, method=method)
        req.add_header("Accept", "application/json")
        if data is not None:
            req.add_header("Content-Type", "application/json")
        if self.token:
            req.add_header("Authorization", f"Bearer {self.token}")
        try:
            with urllib.request.urlopen(req, timeout=timeout) as resp:
                return resp.status, parse_json(resp.read())
        except urllib.error.HTTPError as e:
            raise ServiceError(f"{method} {path}: HTTP {e.code}: {error_message(e)}") from None
        except (socket.timeout, TimeoutError):
            raise PollTimeout() from None
        except urllib.error.URLError as e:
            if isinstance(e.reason, (socket.timeout, TimeoutError)):
                raise PollTimeout() from None
            raise ServiceError(f"{method} {self.server}{path}: {e.reason}") from None


def parse_json(raw: bytes) -> Any:
    return json.loads(raw) if raw.strip() else None


def error_message(e: urllib.error.HTTPError) -> str:
    """The server's `{"error": {"code", "message", "field"?}}`, or the raw body."""
    raw = e.read().decode(errors="replace")
    try:
        err = json.loads(raw)["error"]
        field = f" (field {err['field']})" if err.get("field") else ""
        return f"{err.get('code', '?')}: {err.get('message', '')}{field}"
    except (ValueError, KeyError, TypeError):
        return raw.strip() or str(e.reason)


# --------------------------------------------------------------------------------------------
# The protocol loop
# --------------------------------------------------------------------------------------------

POLL_MS = 2000
ENDED = ("found", "not_found", "cancelled", "failed")


def create_session(client: Client, robot: ToyRobot) -> str:
    body = {"robot": "remote", "start": robot.pose.to_json(), "camera": robot.camera}
    return str(client.call("POST", "/v1/sessions", body)[1]["id"])


def post_goal(client: Client, session: str, goal_class: str) -> str:
    return str(client.call("POST", f"/v1/sessions/{session}/goals", {"class": goal_class})[1]
               ["goal_id"])


def goal_status(client: Client, session: str, goal_id: str) -> dict[str, Any]:
    return client.call("GET", f"/v1/sessions/{session}/goals/{goal_id}")[1] or {}


def next_request(client: Client, session: str) -> Optional[dict[str, Any]]:
    """The next pending request, or None (204, an empty body, or a client-side timeout)."""
    path = f"/v1/sessions/{session}/robot/next?timeout_ms={POLL_MS}"
    try:
        status, body = client.call("GET", path, timeout=POLL_MS / 1000.0 + 10.0)
    except PollTimeout:
        return None
    return body if status == 200 and isinstance(body, dict) and "request_id" in body else None


def send_answer(client: Client, session: str, request_id: Any, body: dict[str, Any]) -> None:
    client.call("POST", f"/v1/sessions/{session}/robot/{request_id}", body)


def cancel_goal(client: Client, session: str, goal_id: str) -> None:
    """Best effort: a goal left behind would wait for answers that never come."""
    try:
        client.call("DELETE", f"/v1/sessions/{session}/goals/{goal_id}")
    except (ServiceError, PollTimeout):
        pass


def serve_goal(client: Client, robot: ToyRobot, session: str, goal_id: str,
               deadline: float, counts: dict[str, int]) -> dict[str, Any]:
    """Answer requests until the goal ends; its last status. Raises GoalTimeout at the
    deadline."""
    status: dict[str, Any] = {}
    while time.monotonic() < deadline:
        started = time.monotonic()
        request = next_request(client, session)
        if request is not None:
            kind = str(request.get("kind"))
            counts[kind] = counts.get(kind, 0) + 1
            send_answer(client, session, request["request_id"],
                        answer(robot, kind, request.get("args")))
            continue
        status = goal_status(client, session, goal_id)
        if status.get("state") in ENDED:
            return status
        if time.monotonic() - started < 0.2:  # a server that does not hold the poll
            time.sleep(0.2)
    raise GoalTimeout(status)


def found_at(status: dict[str, Any]) -> Optional[list[float]]:
    report = status.get("report") or {}
    pose = report.get("reported_pose")
    return list(pose) if status.get("state") == "found" and pose else None


def exit_code(state: Optional[str]) -> int:
    return {"found": 0, "not_found": 3}.get(state or "", 1)


def run(args: argparse.Namespace) -> int:
    client = Client(args.server, args.token)
    robot = ToyRobot()
    counts: dict[str, int] = {}
    summary: dict[str, Any] = {"session": None, "goal_id": None, "state": None,
                               "found_at": None, "requests": 0, "by_kind": counts}
    status: dict[str, Any] = {}
    try:
        summary["session"] = create_session(client, robot)
        summary["goal_id"] = post_goal(client, summary["session"], args.goal)
        deadline = time.monotonic() + args.timeout_s
        status = serve_goal(client, robot, summary["session"], summary["goal_id"], deadline,
                            counts)
    except ServiceError as e:
        print(f"error: {e}", file=sys.stderr)
        summary["error"] = str(e)
    except (GoalTimeout, KeyboardInterrupt) as e:
        status = e.status if isinstance(e, GoalTimeout) else status
        why = (f"no result within {args.timeout_s} s" if isinstance(e, GoalTimeout)
               else "interrupted")
        print(f"error: {why}; cancelling the goal", file=sys.stderr)
        summary["error"] = why
        if summary["goal_id"] is not None:
            cancel_goal(client, summary["session"], summary["goal_id"])
    except (PollTimeout, KeyError, TypeError) as e:
        print(f"error: unexpected answer from the server: {e!r}", file=sys.stderr)
        summary["error"] = f"unexpected answer from the server: {e!r}"
    summary["state"] = status.get("state")
    summary["found_at"] = found_at(status)
    summary["requests"] = sum(counts.values())
    if summary["session"] is not None:
        print(json.dumps(summary))
    return 1 if "error" in summary else exit_code(summary["state"])


# --------------------------------------------------------------------------------------------
# Self-test: the toy robot, without a server
# --------------------------------------------------------------------------------------------


def cell_value(grid: dict[str, Any], x: float, y: float) -> int:
    info = grid["info"]
    res, ox, oy = info["resolution"], info["origin"]["position"]["x"], info["origin"]["position"]["y"]
    col, row = math.floor((x - ox) / res), math.floor((y - oy) / res)
    return grid["data"][row * info["width"] + col]


def aim_at(robot: ToyRobot, standing: Pose, point: tuple[float, float, float]) -> Cone:
    distance = math.hypot(point[0] - standing.x, point[1] - standing.y)
    pan = wrap_angle(math.atan2(point[1] - standing.y, point[0] - standing.x) - standing.yaw)
    tilt = math.atan2(point[2] - robot.camera["height"], distance)
    return Cone(standing, pan, tilt, 1.0)


def self_test() -> int:
    problems: list[str] = []

    def check(ok: bool, what: str) -> None:
        if not ok:
            problems.append(what)

    robot = ToyRobot()
    first = robot.map_update()
    grid, info = first["grid"], first["grid"]["info"]
    w, h = info["width"], info["height"]
    check((w, h) == (62, 52), f"grid is {w} x {h} cells, expected 62 x 52 (60 x 50 + walls)")
    check(len(grid["data"]) == w * h, f"grid data has {len(grid['data'])} cells, not {w * h}")
    check(set(grid["data"]) <= {-1, 0, 100}, "grid data holds values other than -1, 0, 100")
    check(first["newly_known"] == w * h, f"first map update: newly_known {first['newly_known']}")
    check(robot.map_update()["newly_known"] == 0, "second map update: newly_known is not 0")
    check(info["origin"]["position"]["x"] == -0.1 and info["origin"]["position"]["y"] == -0.1,
          "grid origin is not (-0.1, -0.1)")
    walls = [grid["data"][i] for i in range(w)]  # row 0
    walls += [grid["data"][(h - 1) * w + i] for i in range(w)]
    walls += [grid["data"][r * w] for r in range(h)] + [grid["data"][r * w + w - 1] for r in range(h)]
    check(all(v == 100 for v in walls), "the wall ring is not all occupied")
    check(cell_value(grid, 4.0, 3.0) == 100, "the table centre (4.0, 3.0) is not occupied")
    check(cell_value(grid, 3.45, 2.65) == 100 and cell_value(grid, 4.55, 3.35) == 100,
          "the table's corner cells are not occupied")
    check(cell_value(grid, 3.35, 3.0) == 0 and cell_value(grid, 4.0, 3.45) == 0,
          "cells just beside the table are occupied")
    check(cell_value(grid, 1.0, 1.0) == 0, "the start cell (1.0, 1.0) is not free")
    # Row 0 at the bottom: the table's mirror image about the room's middle (y = 2.5) is free.
    check(cell_value(grid, 4.0, 5.0 - 3.0) == 0, "row 0 is not the bottom row (table mirrored)")
    check(grid["data"][1 * w + 1] == 0 and grid["data"][(h - 2) * w + 1] == 0,
          "the room's corner cells next to the walls are not free")

    box = ToyRobot.CEREALBOX
    standing = Pose(box[0] - 1.5, box[1], 0.3)  # 1.5 m west of the box, not facing it exactly
    seen = answer(robot, "process_view_cone",
                  {"cone": cone_json(aim_at(robot, standing, box)), "classes": ["cerealbox"]})
    classes = [d["class"] for d in seen.get("result", {}).get("detections", [])]
    check(classes == ["cerealbox"], f"a cone aimed at the box from 1.5 m saw {seen}")
    check(abs(seen.get("result", {}).get("travelled", -1) - math.hypot(standing.x - 1.0,
                                                                      standing.y - 1.0)) < 1e-9,
          "the view cone's travelled is not the distance from the start")
    away = aim_at(robot, standing, box)
    away = Cone(away.pose, wrap_angle(away.pan + math.pi), away.tilt, 1.0)
    seen = answer(robot, "process_view_cone", {"cone": cone_json(away), "classes": ["cerealbox"]})
    check(seen.get("result", {}).get("detections") == [],
          f"a cone pointed away from the box saw {seen}")
    not_asked = answer(robot, "process_view_cone",
                       {"cone": cone_json(aim_at(robot, standing, box)), "classes": ["mug"]})
    check(not_asked.get("result", {}).get("detections") == [],
          f"a cone asked only for mugs saw {not_asked}")
    table = answer(robot, "process_view_cone",
                   {"cone": cone_json(aim_at(robot, Pose(1.0, 1.0, 0.0), (4.0, 3.0, 0.75))),
                    "classes": ["table", "cerealbox"]})
    check("table" in [d["class"] for d in table.get("result", {}).get("detections", [])],
          f"a cone aimed at the table from the start did not see it: {table}")
    too_low = answer(robot, "process_view_cone",
                     {"cone": cone_json(Cone(standing, 0.0, -1.2, 1.0)), "classes": []})
    check(too_low.get("failure", {}).get("reason") == "invalid_request",
          f"a tilt below the camera's limit was not refused: {too_low}")

    into_table = answer(robot, "move_to", {"goal": {"x": 4.0, "y": 3.0, "yaw": 0.0}})
    check(into_table.get("failure", {}).get("reason") == "unreachable",
          f"move_to into the table: {into_table}")
    beside_table = answer(robot, "move_to", {"goal": {"x": 3.3, "y": 3.0, "yaw": 0.0}})
    check(beside_table.get("failure", {}).get("reason") == "unreachable",
          f"move_to within the robot radius of the table: {beside_table}")
    outside = answer(robot, "move_to", {"goal": {"x": 7.0, "y": 1.0, "yaw": 0.0}})
    check(outside.get("failure", {}).get("reason") == "unreachable",
          f"move_to outside the room: {outside}")
    before = robot.pose
    moved = answer(robot, "move_to", {"goal": {"x": 1.0, "y": 4.0, "yaw": 1.0}})
    check(moved.get("result", {}).get("pose") == {"x": 1.0, "y": 4.0, "yaw": 1.0}
          and abs(moved["result"]["travelled"] - math.hypot(1.0 - before.x, 4.0 - before.y)) < 1e-9,
          f"move_to (1, 4, 1): {moved}")
    for kind in ("classify_place", "detector_scores", "attention", "recognise", "dance"):
        got = answer(robot, kind, {})
        check(got.get("failure", {}).get("reason") == "unsupported", f"{kind}: {got}")
    bad = answer(robot, "move_to", {"goal": {"x": 1.0}})
    check(bad.get("failure", {}).get("reason") == "invalid_request", f"move_to without y: {bad}")
    try:
        json.dumps([first, seen, moved, bad], allow_nan=False)
    except ValueError as e:
        problems.append(f"an answer is not plain JSON: {e}")

    for p in problems:
        print(f"self-test FAILED: {p}")
    if problems:
        return 1
    print("self-test ok")
    return 0


def cone_json(cone: Cone) -> dict[str, Any]:
    return {"pose": cone.pose.to_json(), "pan": cone.pan, "tilt": cone.tilt, "zoom": cone.zoom}


# --------------------------------------------------------------------------------------------


def parse_args(argv: Optional[list[str]] = None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--server", default="http://127.0.0.1:7878", help="the avs serve address")
    p.add_argument("--token", default=os.environ.get("AVS_TOKEN"),
                   help="bearer token (default: $AVS_TOKEN)")
    p.add_argument("--goal", default="cerealbox", help="the object class to search for")
    p.add_argument("--timeout-s", type=float, default=600.0,
                   help="give up (and cancel the goal) after this many seconds")
    p.add_argument("--self-test", action="store_true",
                   help="check the toy robot without a server, then exit")
    return p.parse_args(argv)


def main(argv: Optional[list[str]] = None) -> int:
    args = parse_args(argv)
    return self_test() if args.self_test else run(args)


if __name__ == "__main__":
    sys.exit(main())
