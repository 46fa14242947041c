"""label_cuboids: correct, create and save 3D boxes of a frames folder in rviz (see --help and
docs/labelling.md). The node turns rviz's feedback into edits of session.Session's frames and
draws them back as interactive markers (edit_markers.py). (Over 400 lines: the Labeller's
menus, feedback handlers, clicks and saving all act on one rviz session's state.)"""
import argparse
import os
import signal
import sys
import threading
import time

import rospy
from geometry_msgs.msg import PointStamped, Vector3
from granular_ros.srv import FitCuboid
from interactive_markers.interactive_marker_server import InteractiveMarkerServer
from interactive_markers.menu_handler import MenuHandler
from sensor_msgs.msg import PointCloud2
from std_msgs.msg import String

from ..bag_to_files import offline
from ..bag_to_files.config import BagToFilesConfig
from ..bags import BagError
from ..config_loading import ConfigError
from ..frames_folder import CLOUDS_FOLDER
from ..messages import detection_cuboid, pcd_to_cloud
from ..nodes import missing_master
from ..output import OutputError, resolve, run_main
from ..pcd import CloudError
from .config import load_config
from .edit_markers import (FRAME_MARKER, box_marker, handle_markers, split_handle_name,
                      title_marker)
from .session import BACKUP_FOLDER, TOOL, Session

COMMANDS = "next, previous, first, last, frame N|STAMP, undo, save, class LABEL"
MENU_GROUP = 20  # entries per level of the "Jump to frame" menu
FIT_SERVICE_WAIT = 5.0  # s the first click waits for the cuboid fitter to come up


class UsageError(ValueError):
    status = 2


def parse_args(argv):
    parser = argparse.ArgumentParser(
        prog=TOOL,
        description="Label cuboids in rviz (a ROS node; launch/label_cuboids.launch starts it "
                    "with rviz): every box of a frames folder (pcd/<stamp>.pcd, "
                    "detections_3d/<stamp>.json, as bag_to_files writes it) as an interactive "
                    "marker to move, turn, resize face by face, relabel and delete; new boxes "
                    "from a click with rviz's Publish Point tool, fitted by granular_ros's "
                    "fit_cuboid_server (service fit_cuboid; the launch file starts it); frame "
                    "by frame, with undo. "
                    "Each frame is saved into its detections_3d/<stamp>.json (atomically, "
                    "about a second after the last change, on leaving the frame, on request "
                    "and at the end), keeping every detection not edited byte for byte; the "
                    "file as it was before the first save goes to FRAMES/"
                    f"{BACKUP_FOLDER}/. Topics (in the node's namespace): boxes/* (the "
                    "interactive markers), cloud (sensor_msgs/PointCloud2, latched), frame "
                    "(std_msgs/String 'INDEX/COUNT STAMP', latched), saved (std_msgs/String: "
                    "each file written); it listens to clicked_point (geometry_msgs/"
                    "PointStamped, rviz's Publish Point) and command (std_msgs/String: "
                    f"{COMMANDS}).",
        epilog="A frames folder that another session is labelling, or that cannot be "
               "written, is refused at the start; a detections file that does not parse is "
               "named and its frame skipped (never written). Exit status: 0 when the session "
               "ends (SIGINT or SIGTERM: Ctrl-C, roslaunch stopping, rviz closed) with every "
               "change saved, 1 when a folder is refused or a save failed, 2 on a bad option "
               "or config. See docs/labelling.md.")
    parser.add_argument("--frames", required=True, metavar="FOLDER",
                        help="frames folder to label (pcd/ and detections_3d/)")
    parser.add_argument("--cuboids", metavar="FOLDER",
                        help="folder of <stamp>.json boxes (fit_cuboids' output) that frames "
                             "start from until they are first saved")
    parser.add_argument("--bag", metavar="FILE.bag",
                        help="make FOLDER from this bag with bag_to_files first, unless FOLDER "
                             "already holds frames")
    parser.add_argument("--config", metavar="FILE.yaml",
                        help="classes, sizes and handles, laid over the defaults "
                             "(config/labelling.yaml)")
    parser.add_argument("--frame-id", default="velodyne",
                        help="frame of the clouds and boxes, rviz's fixed frame "
                             "(default: %(default)s)")
    parser.add_argument("--start", metavar="N|STAMP",
                        help="frame to open first: its index from 1 or its stamp (default: 1)")
    parser.add_argument("--relative-to", metavar="DIR",
                        help="folder that relative paths are taken from (launch files pass "
                             "the folder roslaunch was started in)")
    return parser.parse_args(argv)


def frame_index(names, text):
    """The index of frame `text` (an index from 1 or a stamp) in `names`, or None."""
    text = text.strip()
    if text in names:
        return names.index(text)
    if text.isdigit() and 1 <= int(text) <= len(names):
        return int(text) - 1
    return None


class MarkerServer(InteractiveMarkerServer):
    """The interactive marker server, quiet at shutdown: its keep-alive timer (every 0.5 s, no
    handle to stop it) could fire after rospy closed its publisher, and rospy printed the
    ROSException's traceback from the timer's thread."""

    def keepAlive(self, msg):
        try:
            super().keepAlive(msg)
        except rospy.ROSException:
            if not rospy.is_shutdown():
                raise


class Labeller:
    """The node: rviz feedback, clicks and commands in; markers, the cloud and saves out.
    Every callback holds `lock`: rospy runs them on their own threads."""

    def __init__(self, session, config, frame_id):
        self.session, self.config, self.frame_id = session, config, frame_id
        self.lock = threading.RLock()
        self.index, self.labels = 0, None
        self.selected = self.dragging = None
        self.new_class = next(iter(config.classes))
        self.due = {}  # stamp -> time its frame is saved
        self.cloud_problem = self.save_problem = None
        self.server = MarkerServer("~boxes")
        self.cloud_publisher = rospy.Publisher("~cloud", PointCloud2, queue_size=1, latch=True)
        self.frame_publisher = rospy.Publisher("~frame", String, queue_size=1, latch=True)
        self.saved_publisher = rospy.Publisher("~saved", String, queue_size=20)
        self._make_menus()
        self.fit_cuboid = rospy.ServiceProxy("fit_cuboid", FitCuboid)
        self.fit_service_seen = False
        rospy.Subscriber("clicked_point", PointStamped, self.on_click, queue_size=10)
        rospy.Subscriber("~command", String, self.on_command, queue_size=10)

    # ------------------------------------------------------------------ menus

    def _make_menus(self):
        self.box_menu, self.frame_menu = MenuHandler(), MenuHandler()
        label_menu = self.box_menu.insert("Label")
        self.label_entries = {name: self.box_menu.insert(name, parent=label_menu,
                                                         callback=self._label_callback(name))
                              for name in self.config.classes}
        self.box_menu.insert("Delete box", callback=self._with_key(self.delete))
        undo, save = (lambda _: self.undo()), (lambda _: self.save_now())
        step = {"Next frame": lambda _: self.go_to(self.index + 1),
                "Previous frame": lambda _: self.go_to(self.index - 1)}
        self.box_menu.insert("Undo last change", callback=undo)
        self.box_menu.insert("Save now", callback=save)
        for title, callback in step.items():
            self.box_menu.insert(title, callback=callback)
            self.frame_menu.insert(title, callback=callback)
        self._insert_jump_entries(self.frame_menu.insert("Jump to frame"),
                                  list(range(len(self.session.names))))
        new_menu = self.frame_menu.insert("Class of new boxes")
        self.new_class_entries = {name: self.frame_menu.insert(
            name, parent=new_menu, callback=lambda _, name=name: self.set_new_class(name))
            for name in self.config.classes}
        self.frame_menu.insert("Undo last change", callback=undo)
        self.frame_menu.insert("Save now", callback=save)

    def _insert_jump_entries(self, parent, indices):
        """Frames under `parent` in nested groups of at most MENU_GROUP entries."""
        if len(indices) <= MENU_GROUP:
            for i in indices:
                self.frame_menu.insert(f"{i + 1}  {self.session.names[i]}", parent=parent,
                                       callback=lambda _, i=i: self.go_to(i))
            return
        chunk = MENU_GROUP
        while len(indices) > chunk * MENU_GROUP:
            chunk *= MENU_GROUP
        for start in range(0, len(indices), chunk):
            part = indices[start:start + chunk]
            group = self.frame_menu.insert(f"{part[0] + 1} - {part[-1] + 1}", parent=parent)
            self._insert_jump_entries(group, part)

    def _label_callback(self, name):
        return self._with_key(lambda key: self.set_label(key, name))

    def _with_key(self, action):
        return lambda feedback: action(feedback.marker_name)

    # ------------------------------------------------------------------ drawing

    def name(self):
        return self.session.names[self.index]

    def title_lines(self):
        """Short lines: the title floats in the scene, where long ones hide boxes; the log
        has the details of a problem."""
        state = "unsaved changes" if self.session.unsaved(self.name()) else "saved"
        lines = [f"frame {self.index + 1}/{len(self.session.names)}", self.name(),
                 f"{len(self.labels.boxes())} boxes, new: {self.new_class}", state]
        if self.session.skipped:
            lines.append(f"{len(self.session.skipped)} frames skipped (see the log)")
        if self.cloud_problem:
            lines.append("CLOUD UNREADABLE (see the log)")
        if self.save_problem:
            lines.append("NOT SAVED (see the log)")
        return lines

    def _insert_box(self, entry):
        if entry.key != self.dragging:
            self.server.insert(box_marker(entry, self.frame_id, self.config.classes,
                                          entry.key == self.selected, self.config.handles),
                               self.on_box_feedback)
            label = entry.detection.get("label")
            for name, handle in self.label_entries.items():
                self.box_menu.setCheckState(handle, self.box_menu.CHECKED if name == label
                                            else self.box_menu.UNCHECKED)
            self.box_menu.apply(self.server, entry.key)
        if entry.key == self.selected:
            for handle in handle_markers(entry, self.frame_id, self.config.handles):
                if handle.name != self.dragging:
                    self.server.insert(handle, self.on_handle_feedback)

    def _insert_title(self):
        for name, handle in self.new_class_entries.items():
            self.frame_menu.setCheckState(handle, self.frame_menu.CHECKED if name == self.new_class
                                          else self.frame_menu.UNCHECKED)
        # The title takes only menu choices: other feedback (clicks on it) is ignored.
        self.server.insert(title_marker(self.title_lines(), self.frame_id,
                                        bool(self.cloud_problem or self.save_problem)),
                           lambda feedback: None)
        self.frame_menu.apply(self.server, FRAME_MARKER)

    def redraw(self):
        """Every marker of the frame."""
        self.server.clear()
        for entry in self.labels.boxes():
            self._insert_box(entry)
        self.redraw_title()

    def redraw_box(self, key):
        """Box `key`'s markers (but the one being dragged) and the title."""
        entry = self.labels.find(key)
        if entry is not None and entry.box is not None:
            self._insert_box(entry)
        self.redraw_title()

    def redraw_title(self):
        self._insert_title()
        self.server.applyChanges()

    # ------------------------------------------------------------------ frames

    def go_to(self, index):
        with self.lock:
            if not 0 <= index < len(self.session.names):
                rospy.loginfo("%s: no frame %d (frames 1 to %d)", TOOL, index + 1,
                              len(self.session.names))
                return
            if self.labels is not None:
                self.save(self.name())
            self.index, self.selected, self.dragging = index, None, None
            self.labels = self.session.load(self.name())
            self._load_cloud()
            self.redraw()
            self.frame_publisher.publish(String(
                f"{self.index + 1}/{len(self.session.names)} {self.name()}"))

    def _load_cloud(self):
        path = self.session.pcd_path(self.name())
        self.cloud_problem = None
        try:
            self.cloud_publisher.publish(pcd_to_cloud(path, self.frame_id, rospy.Time.now()))
        except (OSError, CloudError) as error:
            self.cloud_problem = str(error)
            rospy.logerr("%s: %s: %s", TOOL, path, error)

    # ------------------------------------------------------------------ edits

    def changed(self, key=None):
        """After an edit: the frame is saved once it rests; box `key` (None: all) redrawn."""
        self.due[self.name()] = time.monotonic() + self.config.save_debounce
        if key is None:
            self.redraw()
        else:
            self.redraw_box(key)

    def on_box_feedback(self, feedback):
        self._on_feedback(feedback, feedback.marker_name, None)

    def on_handle_feedback(self, feedback):
        key, face = split_handle_name(feedback.marker_name)
        self._on_feedback(feedback, key, face)

    def _on_feedback(self, feedback, key, face):
        with self.lock:
            if feedback.event_type == feedback.MOUSE_DOWN:
                self.labels.begin_gesture()
                self.dragging = feedback.marker_name
            elif feedback.event_type == feedback.MOUSE_UP:
                self.labels.end_gesture()
                self.dragging = None
                self.selected = key
                self.redraw()
            elif feedback.event_type == feedback.POSE_UPDATE:
                p, q = feedback.pose.position, feedback.pose.orientation
                if face is None:
                    edited = self.labels.move_to_pose(key, (p.x, p.y, p.z), (q.x, q.y, q.z, q.w))
                else:
                    edited = self.labels.drag_face(key, face, (p.x, p.y, p.z))
                if edited:
                    self.changed(key)

    def set_label(self, key, label):
        with self.lock:
            if self.labels.set_label(key, label):
                self.changed(key)

    def delete(self, key):
        with self.lock:
            if self.labels.delete(key):
                self.selected = None if self.selected == key else self.selected
                self.changed()

    def undo(self):
        with self.lock:
            if not self.labels.undo():
                rospy.loginfo("%s: nothing to undo in frame %s", TOOL, self.name())
                return
            self.dragging = None
            if self.labels.find(self.selected) is None:
                self.selected = None
            self.changed()

    def set_new_class(self, name):
        with self.lock:
            self.new_class = name
            self.redraw_title()

    def on_click(self, message):
        with self.lock:
            if message.header.frame_id not in ("", self.frame_id):
                rospy.logwarn("%s: click in frame '%s' ignored: boxes are in '%s' (set "
                              "rviz's fixed frame to it)", TOOL, message.header.frame_id,
                              self.frame_id)
                return
            size = self.config.classes[self.new_class].size
            try:
                if not self.fit_service_seen:
                    rospy.wait_for_service(self.fit_cuboid.resolved_name, FIT_SERVICE_WAIT)
                    self.fit_service_seen = True
                cloud_file = os.path.abspath(self.session.pcd_path(self.name()))
                reply = self.fit_cuboid(cloud_file=cloud_file, click=message.point,
                                        label=self.new_class, size=Vector3(*size))
            except (rospy.ROSException, rospy.ServiceException) as error:
                rospy.logerr("%s: no new box: the cuboid fitter (%s, granular_ros's "
                             "fit_cuboid_server, which label_cuboids.launch starts) did not "
                             "answer: %s", TOOL, self.fit_cuboid.resolved_name, error)
                return
            if reply.error:
                rospy.logerr("%s: no new box at the click: %s", TOOL, reply.error)
                return
            box = detection_cuboid(reply.cuboid)
            self.selected = self.labels.add(self.new_class, box)
            how = f"fitted to {reply.points} points" if reply.points else \
                "the class's default size: too few points near the click"
            rospy.loginfo("%s: new %s at (%.2f, %.2f), %.2f x %.2f x %.2f m, %s", TOOL,
                          self.new_class, box.centre[0], box.centre[1], *box.size, how)
            self.changed()

    def on_command(self, message):
        words = message.data.strip().split(None, 1)
        command, argument = (words + ["", ""])[:2] if words else ("", "")
        with self.lock:
            if command in ("next", "previous"):
                self.go_to(self.index + (1 if command == "next" else -1))
            elif command in ("first", "last"):
                self.go_to(0 if command == "first" else len(self.session.names) - 1)
            elif command == "frame" and frame_index(self.session.names, argument) is not None:
                self.go_to(frame_index(self.session.names, argument))
            elif command == "undo":
                self.undo()
            elif command == "save":
                self.save_now()
            elif command == "class" and argument in self.config.classes:
                self.set_new_class(argument)
            else:
                rospy.logwarn("%s: unknown command %r (commands: %s; classes: %s)", TOOL,
                              message.data, COMMANDS, ", ".join(self.config.classes))

    # ------------------------------------------------------------------ saving

    def save(self, name):
        """Save frame `name` if it changed; False when that failed (the title says why)."""
        self.due.pop(name, None)
        try:
            path = self.session.save(name)
        except OutputError as error:
            self.save_problem = str(error)
            rospy.logerr("%s: %s", TOOL, error)
            return False
        self.save_problem = None
        if path:
            rospy.loginfo("%s: saved %s", TOOL, path)
            self.saved_publisher.publish(String(path))
        return True

    def save_now(self):
        with self.lock:
            self.save(self.name())
            self.redraw_title()

    def save_due(self):
        with self.lock:
            now = time.monotonic()
            for name in [n for n, due in self.due.items() if due <= now]:
                self.save(name)
                if name == self.name():
                    self.redraw_title()

    def save_all(self):
        """Save every changed frame; OutputError naming those that could not be."""
        with self.lock:
            failed = [name for name in self.session.names
                      if self.session.unsaved(name) and not self.save(name)]
        if failed:
            raise OutputError(f"{len(failed)} frames not saved ({', '.join(failed[:3])}"
                              f"{' ...' if len(failed) > 3 else ''}); their changes are lost: "
                              "the errors above say why")


def _prepare_frames(args):
    """FOLDER made from --bag when it holds no frames yet; its exit status."""
    if os.path.isdir(os.path.join(args.frames, CLOUDS_FOLDER)) and os.listdir(
            os.path.join(args.frames, CLOUDS_FOLDER)):
        print(f"{TOOL}: {args.frames} holds frames already: labelling them; {args.bag} is not "
              "converted again", file=sys.stderr)
        return 0
    # A bag without boxes (a real sensor's) gives every cloud, to be labelled from scratch.
    try:
        clouds_only = not offline.has_detections(args.bag, BagToFilesConfig())
    except BagError as error:
        print(f"{TOOL}: {error}", file=sys.stderr)
        return 1
    return offline.main(["--bag", args.bag, "--out", args.frames]
                        + (["--clouds-only"] if clouds_only else []))


def serve(session, config, args, start):
    """The node's life, with the session open: until a stop signal, then every change saved."""
    problem = missing_master("use launch/label_cuboids.launch, which starts one")
    if problem:
        raise OutputError(problem)
    stop = threading.Event()
    # A session ends by saving, not by unwinding mid-write: the handlers only ask for a stop.
    for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(signum, lambda *_: stop.set())
    rospy.init_node(TOOL, disable_signals=True)
    labeller = Labeller(session, config, args.frame_id)
    for reason in session.skipped.values():
        rospy.logerr("%s: frame skipped, its file is never written: %s", TOOL, reason)
    labeller.go_to(start)
    rospy.loginfo("%s: %d frames of %s (%d skipped); backups in %s", TOOL, len(session.names),
                  session.frames, len(session.skipped), session.backup_folder)
    try:
        while not stop.is_set() and not rospy.is_shutdown():
            stop.wait(0.05)
            labeller.save_due()
    finally:
        labeller.save_all()
        rospy.signal_shutdown("session ended")
    return 0


def main(argv=None):
    args = parse_args(rospy.myargv(sys.argv)[1:] if argv is None else argv)
    for option in ("frames", "cuboids", "bag", "config"):
        setattr(args, option, resolve(getattr(args, option), args.relative_to))

    def body():
        try:
            config = load_config(args.config)
        except ConfigError as error:
            raise UsageError(str(error)) from error
        if args.bag:
            status = _prepare_frames(args)
            if status != 0:
                return status
        session = Session(args.frames, args.cuboids, args.frame_id, config.min_size)
        with session.opened():
            start = frame_index(session.names, args.start) if args.start else 0
            if start is None:
                raise UsageError(f"--start {args.start}: no such frame (1 to "
                                 f"{len(session.names)}, or a stamp of pcd/)")
            return serve(session, config, args, start)

    return run_main(TOOL, body)
