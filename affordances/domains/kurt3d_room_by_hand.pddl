; The KURT3D's room written by hand: what a person who knows the simulator's worlds would say
; each behaviour does. The upper bound the learned domain is measured against
; (kurt_plan --pddl-domain). Categories a person would name (liftable, pushable, stiff, flush)
; stand where the learned domain has conditions read off its classifiers; the rest of the
; vocabulary is the one the robot's perception gives (affordances/README.md, "The scene's atoms").
(define (domain kurt3d-room)
  (:requirements :strips :typing :negative-preconditions)
  (:types
    location - object
    thing - location
    place - location
    switch - place
    door - place)
  (:predicates
    (robot-at ?l - location)
    (hand-free)
    (holding ?t - thing)
    (on ?t - thing ?s - switch)
    (loaded ?s - switch)
    (pressed ?s - switch)
    (open ?d - door)
    (beyond ?d - door)
    (opens ?s - switch ?d - door)
    (liftable ?t - thing)
    (pushable ?t - thing)
    (flush ?s - switch)
    (stiff ?s - switch))

  ; Drives (carrying what it holds) to a thing or a place.
  (:action go
    :parameters (?from - location ?to - location)
    :precondition (and (robot-at ?from))
    :effect (and (robot-at ?to) (not (robot-at ?from))))

  ; The crane's magnet lifts a thing light and magnetizable enough.
  (:action lift
    :parameters (?t - thing)
    :precondition (and (robot-at ?t) (hand-free) (liftable ?t))
    :effect (and (holding ?t) (not (hand-free))))

  ; Puts what it holds down on a switch's platform; one thing presses a switch that is not stiff.
  (:action put-down
    :parameters (?t - thing ?s - switch ?d - door)
    :precondition (and (holding ?t) (robot-at ?s) (opens ?s ?d) (not (stiff ?s)))
    :effect (and (on ?t ?s) (loaded ?s) (pressed ?s) (open ?d) (hand-free) (not (holding ?t))))

  ; A stiff switch: the first thing only loads it...
  (:action put-down-first-on-stiff
    :parameters (?t - thing ?s - switch)
    :precondition (and (holding ?t) (robot-at ?s) (stiff ?s) (not (loaded ?s)))
    :effect (and (on ?t ?s) (loaded ?s) (hand-free) (not (holding ?t))))

  ; ... the second presses it.
  (:action put-down-second-on-stiff
    :parameters (?t - thing ?s - switch ?d - door)
    :precondition (and (holding ?t) (robot-at ?s) (stiff ?s) (loaded ?s) (opens ?s ?d))
    :effect (and (on ?t ?s) (pressed ?s) (open ?d) (hand-free) (not (holding ?t))))

  ; Pushes a thing onto a switch set flush with the floor, ending where the switch is.
  (:action push
    :parameters (?t - thing ?s - switch ?d - door)
    :precondition (and (robot-at ?t) (hand-free) (pushable ?t) (flush ?s) (opens ?s ?d))
    :effect (and (on ?t ?s) (loaded ?s) (pressed ?s) (open ?d) (robot-at ?s) (not (robot-at ?t))))

  ; Drives through an open door.
  (:action drive-through
    :parameters (?d - door)
    :precondition (and (robot-at ?d) (open ?d) (hand-free))
    :effect (and (beyond ?d))))
