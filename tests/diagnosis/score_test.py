"""The suite's scoring (run_suite.py) of verdicts that name only the model's structure: a
null on which the gap finder corrects the model's idealisations (found, or ambiguous
between two such corrections) reports no physics; an ambiguity with physics in it does.

Usage: score_test.py
"""
import os
import sys
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import run_suite  # noqa: E402

NULL = {"effect": "none"}


def effect(eid, structural):
    return {"id": eid, "structural": structural, "params": {}}


def result(verdict, effects):
    return {"case": "c", "verdict": verdict, "effects": effects, "runners_up": [],
            "wall_seconds": 1.0, "errors": {}}


class StructureOnly(unittest.TestCase):
    def outcome(self, r, answer=NULL):
        return run_suite.outcome(run_suite.score(r, answer), answer)

    def test_a_found_structure_on_a_null_is_structure_only(self):
        r = result("found", [effect("friction.anisotropic", ["friction.anisotropic"])])
        self.assertEqual(self.outcome(r), "structure only")

    def test_an_ambiguity_between_two_structures_on_a_null_is_structure_only(self):
        # mujoco-null-slippery, session 47: finite friction or creeping contact.
        r = result("ambiguous", [effect("friction.anisotropic", ["friction.anisotropic"]),
                                 effect("contact.creep", ["contact.creep"])])
        self.assertEqual(self.outcome(r), "structure only")

    def test_an_ambiguity_with_physics_in_it_is_not(self):
        r = result("ambiguous", [effect("friction.anisotropic", ["friction.anisotropic"]),
                                 effect("tether.constant", [])])
        self.assertEqual(self.outcome(r), "ambiguous, not")

    def test_an_ambiguity_that_names_the_truth_stays_so(self):
        answer = {"effect": "tether.constant", "accept": ["tether.constant"]}
        r = result("ambiguous", [effect("contact.creep", ["contact.creep"]),
                                 effect("tether.constant", [])])
        self.assertEqual(self.outcome(r, answer), "ambiguous, truth named")


if __name__ == "__main__":
    unittest.main()
