# An Otter-Grader test (OK format) for the observer gain of the exercise
# stoustrup-pole-assignment: the student's notebook defines L; each case is a doctest that
# Otter runs in the notebook's namespace. The first case gives the points for a right gain;
# the second, hidden, prints the workbench's feedback, which names the mistake of a wrong one.
OK_FORMAT = True

test = {
    "name": "q_gain",
    "points": 2,
    "suites": [
        {
            "cases": [
                {
                    "code": (
                        ">>> import observer_workbench as owb\n"
                        ">>> result = owb.check('stoustrup-pole-assignment', {'L': L})\n"
                        ">>> result.part('L')['verdict']\n"
                        "'correct'\n"
                    ),
                    "hidden": False,
                    "locked": False,
                },
                {
                    "code": (
                        ">>> import observer_workbench as owb\n"
                        ">>> feedback = owb.check('stoustrup-pole-assignment', {'L': L}).part('L')\n"
                        ">>> feedback['mistake'] is None, feedback['feedback']\n"
                        "(True, 'correct')\n"
                    ),
                    "hidden": True,
                    "locked": False,
                },
            ],
            "scored": True,
            "setup": "",
            "teardown": "",
            "type": "doctest",
        }
    ],
}
