; A small PDDL problem written by `avs examples` for find_domain.pddl: the shipped office floor
; (a corridor with office1, the kitchen and office2 off it), the robot in the corridor, the
; cereal box in the kitchen. The cheapest plan drives to the kitchen, looks and reports: cost 6.
; Run: avs plan find_domain.pddl find_problem.pddl
(define (problem find-cerealbox)
  (:domain find-object)
  (:objects
    corridor office1 kitchen office2 - room
    cerealbox stapler - item)
  (:init
    (robot-at corridor)
    (door corridor office1) (door office1 corridor)
    (door corridor kitchen) (door kitchen corridor)
    (door corridor office2) (door office2 corridor)
    (= (distance corridor office1) 3) (= (distance office1 corridor) 3)
    (= (distance corridor kitchen) 4) (= (distance kitchen corridor) 4)
    (= (distance corridor office2) 6) (= (distance office2 corridor) 6)
    (in cerealbox kitchen)
    (in stapler office1)
    (= (total-cost) 0))
  (:goal (reported cerealbox))
  (:metric minimize (total-cost)))
