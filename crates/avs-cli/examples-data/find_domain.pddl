; A small PDDL domain written by `avs examples` for `avs plan` (STRIPS with typing, negative
; preconditions and action costs): a robot drives between rooms through doors, looks for an
; object in the room it is in, and reports it once seen. Driving costs the distance; looking
; and reporting cost 1.
; Run: avs plan find_domain.pddl find_problem.pddl
(define (domain find-object)
  (:requirements :strips :typing :negative-preconditions :action-costs)
  (:types room item)
  (:predicates
    (robot-at ?r - room)
    (door ?from ?to - room)
    (in ?i - item ?r - room)
    (seen ?i - item)
    (reported ?i - item))
  (:functions
    (total-cost) - number
    (distance ?from ?to - room) - number)
  (:action drive
    :parameters (?from ?to - room)
    :precondition (and (robot-at ?from) (door ?from ?to))
    :effect (and (not (robot-at ?from)) (robot-at ?to)
                 (increase (total-cost) (distance ?from ?to))))
  (:action look
    :parameters (?i - item ?r - room)
    :precondition (and (robot-at ?r) (in ?i ?r))
    :effect (and (seen ?i) (increase (total-cost) 1)))
  (:action report
    :parameters (?i - item)
    :precondition (and (seen ?i) (not (reported ?i)))
    :effect (and (reported ?i) (increase (total-cost) 1))))
