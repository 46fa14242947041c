"""Tracking figures of predicted cuboids whose ids are track ids, against truths whose ids are
vehicles (the simulator's detection ids): CLEAR MOT's MOTA and identity switches, and how many
frames a track needs to settle on its class (docs/tracking.md).

A frame's correspondences are evaluate_cuboids' pairs (Hungarian on the x-y centre distance,
gated) that pass the paper's criterion: a miss and a false positive are exactly the per-frame
F1's FN and FP under that criterion, and "don't care" truths stay don't care. A vehicle that
was last followed by track h and is now followed by another track is an identity switch
(Bernardin and Stiefelhagen 2008, "Evaluating Multiple Object Tracking Performance: The
CLEAR MOT Metrics"). MOTA = 1 - (FN + FP + IDSW) / truths."""
import collections

from .cuboid_matching import counts_as, distribution

CRITERION = "paper"


class TrackTally:
    """Counts over a drive's frames, in stamp order."""

    def __init__(self, class_map):
        self.class_map = class_map
        self.truths = self.predictions = self.tp = self.switches = 0
        self.last_track = {}  # vehicle id -> the track that last followed it
        self.vehicles, self.tracks = set(), set()
        # track id -> [(predicted label, true label)] over the frames it followed a vehicle
        self.followed = collections.defaultdict(list)
        self.final_label = {}  # track id -> its label in its last frame (its vote over all)

    def add(self, result):
        """One frame's FrameResult (evaluate_frame)."""
        self.truths += len(result.truths) - len(result.ignored_truths)
        self.predictions += len(result.predictions) - len(result.ignored_predictions)
        for prediction in result.predictions:
            self.final_label[prediction.id] = prediction.label
        for ti, pi, _, passed, _ in result.pairs:
            if not passed[CRITERION]:
                continue
            truth, prediction = result.truths[ti], result.predictions[pi]
            self.tp += 1
            self.vehicles.add(truth.id)
            self.tracks.add(prediction.id)
            last = self.last_track.get(truth.id)
            if last is not None and last != prediction.id:
                self.switches += 1
            self.last_track[truth.id] = prediction.id
            self.followed[prediction.id].append((prediction.label, truth.label))

    def settling(self):
        """Per track that followed a vehicle: the frame (1 = its first frame following one)
        from which its label counts as the true label of the vehicle it followed most, in
        every frame after; None when its last frame's label is wrong."""
        frames = {}
        for track, labels in self.followed.items():
            true_label = collections.Counter(t for _, t in labels).most_common(1)[0][0]
            settled = None
            for k in range(len(labels), 0, -1):
                if not counts_as(labels[k - 1][0], true_label, self.class_map):
                    break
                settled = k
            frames[track] = settled
        return frames

    def class_aware_f1_per_track(self):
        """The paper's criterion's class-aware F1 with each track named by its final class
        (its label in its last frame: the vote over all its frames) in every frame."""
        tp = sum(counts_as(self.final_label[track], true_label, self.class_map)
                 for track, labels in self.followed.items() for _, true_label in labels)
        total = self.truths + self.predictions
        return 2.0 * tp / total if total else None

    def summary(self):
        fp, fn = self.predictions - self.tp, self.truths - self.tp
        settling = self.settling()
        settled = [k for k in settling.values() if k is not None]
        return {
            "criterion": CRITERION,
            "truths": self.truths, "predictions": self.predictions, "tp": self.tp,
            "fp": fp, "fn": fn, "id_switches": self.switches,
            "mota": 1.0 - (fn + fp + self.switches) / self.truths if self.truths else None,
            "id_switches_per_100_track_frames":
                100.0 * self.switches / self.tp if self.tp else None,
            "vehicles_followed": len(self.vehicles), "tracks_following": len(self.tracks),
            "tracks_per_vehicle": len(self.tracks) / len(self.vehicles) if self.vehicles
            else None,
            "class_aware_f1_per_track": self.class_aware_f1_per_track(),
            "class_settled_tracks": len(settled),
            "frames_to_settle": distribution(settled),
        }
