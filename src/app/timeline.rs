//! The timeline's model: keys (a time and the pose of every hand; key 0 is the scene's initial
//! pose at time 0), one cached solved frame per key, the scrub position and playback. Frames are
//! solved in order in the background; changing key `k` drops the cached frames from `k` on and
//! keeps the earlier ones.

use super::jobs::{Pose, Solution};
use super::pose::HandInfo;
use crate::scene::{KeyframeDef, Scene};
use std::collections::BTreeMap;

/// One key of the timeline.
#[derive(Clone, Debug, PartialEq)]
pub struct Key {
    /// Time, s.
    pub time: f64,
    /// Joint angles of every hand (for a grasp keyframe, its preshape: the timeline shows it
    /// there; the grasp itself runs from the Joints panel's Grasp row or `prehensile solve`).
    pub pose: Pose,
    /// The scene's grasp keyframes at this time, kept as written so that saving the scene
    /// keeps them.
    pub grasps: Vec<KeyframeDef>,
}

/// Keys, cached frames and playback.
#[derive(Default)]
pub struct Timeline {
    /// Keys in increasing time; key 0 at time 0.
    pub keys: Vec<Key>,
    /// The solved frame of each key, when cached.
    pub frames: Vec<Option<Solution>>,
    /// The key shown (scrub position).
    pub current: usize,
    /// Playing.
    pub playing: bool,
    /// Start again at the end.
    pub looping: bool,
    /// Seconds of playback since the current key was reached.
    pub elapsed: f64,
}

impl Timeline {
    /// The keys of `scene`: its initial pose at time 0, then one key per distinct keyframe time
    /// (joints a keyframe does not name keep their previous angle).
    pub fn from_scene(scene: &Scene, hands: &[HandInfo]) -> Result<Timeline, String> {
        let mut pose: Pose = Vec::new();
        for h in hands {
            let named = scene.body[h.body].pose.clone().unwrap_or_default();
            let angles = h
                .skeleton
                .apply_pose(&h.skeleton.rest_angles(), &named)
                .map_err(|e| format!("body \"{}\": {e}", h.name))?;
            pose.push((h.body, angles));
        }
        let mut keys = vec![Key {
            time: 0.0,
            pose,
            grasps: Vec::new(),
        }];
        for (i, k) in scene.keyframe.iter().enumerate() {
            let hand = match &k.body {
                Some(name) => hands.iter().position(|h| &h.name == name),
                None => (!hands.is_empty()).then_some(0),
            }
            .ok_or_else(|| format!("keyframe[{i}]: no such hand"))?;
            let mut pose = keys.last().expect("key 0").pose.clone();
            let skeleton = &hands[hand].skeleton;
            let mut angles = pose[hand].1.clone();
            // A grasp keyframe shows its preshape.
            if let Some(g) = &k.grasp {
                let preshape = match &g.preshape {
                    Some(crate::scene::PreshapeDef::Pose(p)) => p.clone(),
                    Some(crate::scene::PreshapeDef::Named(n)) => {
                        crate::hand::synergy::Preshape::from_name(n)
                            .map(|p| p.pose())
                            .unwrap_or_default()
                    }
                    None => crate::hand::synergy::Preshape::Power.pose(),
                };
                angles = skeleton
                    .apply_pose(&angles, &preshape)
                    .map_err(|e| format!("keyframe[{i}].grasp.preshape: {e}"))?;
            }
            pose[hand].1 = skeleton
                .apply_pose(&angles, &k.pose)
                .map_err(|e| format!("keyframe[{i}]: {e}"))?;
            let grasps: Vec<KeyframeDef> =
                k.grasp.is_some().then(|| k.clone()).into_iter().collect();
            let last = keys.last_mut().expect("key 0");
            if k.time == last.time {
                last.pose = pose;
                last.grasps.extend(grasps);
            } else {
                keys.push(Key {
                    time: k.time,
                    pose,
                    grasps,
                });
            }
        }
        let frames = vec![None; keys.len()];
        Ok(Timeline {
            keys,
            frames,
            ..Default::default()
        })
    }

    /// Writes the keys into `scene`: key 0 as the hands' initial `pose`, the others as
    /// keyframes naming every joint.
    pub fn write_to(&self, scene: &mut Scene, hands: &[HandInfo]) {
        let named =
            |h: &HandInfo, angles: &[f64]| -> BTreeMap<String, f64> { h.skeleton.pose_of(angles) };
        scene.keyframe.clear();
        for (k, key) in self.keys.iter().enumerate() {
            for (h, (_, angles)) in hands.iter().zip(&key.pose) {
                let grasp = key
                    .grasps
                    .iter()
                    .find(|g| g.body.as_ref().is_none_or(|b| *b == h.name));
                if let (Some(g), true) = (grasp, k > 0) {
                    // A grasp keyframe as the scene wrote it, at the key's time.
                    scene.keyframe.push(KeyframeDef {
                        time: key.time,
                        ..g.clone()
                    });
                } else if k == 0 {
                    scene.body[h.body].pose = Some(named(h, angles));
                } else {
                    scene.keyframe.push(KeyframeDef {
                        time: key.time,
                        body: (hands.len() > 1).then(|| h.name.clone()),
                        pose: named(h, angles),
                        grasp: None,
                    });
                }
            }
        }
    }

    /// Drops the cached frames from key `from` on.
    pub fn invalidate_from(&mut self, from: usize) {
        self.frames.resize(self.keys.len(), None);
        for f in self.frames.iter_mut().skip(from) {
            *f = None;
        }
    }

    /// Adds `pose` as a key after the current one (half-way to the next key, or one second
    /// after the last); returns its index.
    pub fn add_key(&mut self, pose: Pose) -> usize {
        let i = self.current.min(self.keys.len().saturating_sub(1));
        let time = match (self.keys.get(i), self.keys.get(i + 1)) {
            (Some(a), Some(b)) => 0.5 * (a.time + b.time),
            (Some(a), None) => a.time + 1.0,
            _ => 0.0,
        };
        let at = (i + 1).min(self.keys.len());
        self.keys.insert(
            at,
            Key {
                time,
                pose,
                grasps: Vec::new(),
            },
        );
        self.frames.insert(at, None);
        self.invalidate_from(at);
        self.current = at;
        at
    }

    /// Deletes key `k` (not key 0).
    pub fn delete_key(&mut self, k: usize) {
        if k == 0 || k >= self.keys.len() {
            return;
        }
        self.keys.remove(k);
        self.frames.remove(k);
        self.invalidate_from(k);
        self.current = self.current.min(self.keys.len() - 1);
    }

    /// Moves key `k` to `time`, kept strictly between its neighbours (the order of the keys,
    /// and so the cached frames, do not change).
    pub fn move_key(&mut self, k: usize, time: f64) {
        if k == 0 || k >= self.keys.len() || !time.is_finite() {
            return;
        }
        let lo = self.keys[k - 1].time + 1e-3;
        let hi = self
            .keys
            .get(k + 1)
            .map_or(f64::INFINITY, |n| n.time - 1e-3);
        if lo <= hi {
            self.keys[k].time = time.clamp(lo, hi);
        }
    }

    /// Replaces the pose of key `k`: its frame and the later ones are solved again.
    pub fn set_pose(&mut self, k: usize, pose: Pose) {
        if let Some(key) = self.keys.get_mut(k) {
            if key.pose != pose {
                key.pose = pose;
                self.invalidate_from(k);
            }
        }
    }

    /// The first key without a cached frame.
    pub fn first_unsolved(&self) -> Option<usize> {
        self.frames.iter().position(Option::is_none)
    }

    /// Advances playback by `dt` seconds: moves to the next key when its time has come and its
    /// frame is solved (playback waits for the solver otherwise). Returns `true` when the
    /// current key changed.
    pub fn advance(&mut self, dt: f64) -> bool {
        if !self.playing || self.keys.len() < 2 {
            return false;
        }
        self.elapsed += dt;
        let next = if self.current + 1 < self.keys.len() {
            self.current + 1
        } else if self.looping {
            0
        } else {
            self.playing = false;
            return false;
        };
        let gap = if next == 0 {
            0.5
        } else {
            self.keys[next].time - self.keys[self.current].time
        };
        if self.elapsed >= gap && self.frames.get(next).is_some_and(Option::is_some) {
            self.current = next;
            self.elapsed = 0.0;
            return true;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::pose::hands_of;

    fn timeline() -> (Scene, Vec<HandInfo>, Timeline) {
        let scene =
            Scene::parse(include_str!("../../assets/scenes/hand-and-ball.toml"), "t").unwrap();
        let hands = hands_of(&scene);
        let t = Timeline::from_scene(&scene, &hands).unwrap();
        (scene, hands, t)
    }

    #[test]
    fn keys_round_trip_through_the_scene() {
        let (mut scene, hands, t) = timeline();
        assert_eq!(t.keys.len(), 3);
        assert_eq!(t.keys[2].time, 2.0);
        t.write_to(&mut scene, &hands);
        let text = toml::to_string(&scene).unwrap();
        let again = Scene::parse(&text, "again").unwrap();
        let t2 = Timeline::from_scene(&again, &hands).unwrap();
        assert_eq!(t.keys, t2.keys);
    }

    #[test]
    fn keys_are_added_moved_and_deleted_in_order() {
        let (_, _, mut t) = timeline();
        assert_eq!(t.first_unsolved(), Some(0));
        let mut p = t.keys[1].pose.clone();
        p[0].1[0] += 5.0;
        t.current = 1;
        let k = t.add_key(p.clone());
        assert_eq!(k, 2);
        assert!(t.keys[1].time < t.keys[2].time && t.keys[2].time < t.keys[3].time);
        t.move_key(2, 100.0);
        assert!(
            t.keys[2].time < t.keys[3].time,
            "a key cannot pass its neighbour"
        );
        t.delete_key(2);
        assert_eq!(t.keys.len(), 3);
        t.delete_key(0);
        assert_eq!(t.keys.len(), 3, "key 0 stays");
    }
}
