; The KURT3D's room written by hand: what a person who knows the simulator's worlds would say
; each behaviour does, in the vocabulary the robot's perception gives (affordances/README.md,
; "The scene's atoms"). The upper bound a learned domain is measured against
; (kurt_plan --pddl-domain). What the person cannot see either stays uncertain: whether a can
; comes up (a lift comes off about half the time, and a thing of the colour of one that did not
; come up is not worth trying: in these rooms a colour is a material), whether a switch is stiff
; (one thing presses most switches; a second always does). A box is what a person would push.
(define (domain kurt3d-room)
  (:requirements :strips :typing :negative-preconditions :probabilistic-effects)
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
    (tried ?t - thing)
    (like-failed ?t - thing)
    (on ?t - thing ?s - switch)
    (loaded ?s - switch)
    (pressed ?s - switch)
    (open ?d - door)
    (beyond ?d - door)
    (opens ?s - switch ?d - door)
    (box ?t - thing)
    (flush ?s - switch))

  ; Drives (carrying what it holds) to a thing or a place.
  (:action go
    :parameters (?from - location ?to - location)
    :precondition (and (robot-at ?from))
    :effect (and (robot-at ?to) (not (robot-at ?from))))

  ; The crane's magnet tries a thing once: it comes up if light and magnetizable.
  (:action lift
    :parameters (?t - thing)
    :precondition (and (robot-at ?t) (hand-free) (not (tried ?t)) (not (like-failed ?t)) (not (box ?t)))
    :effect (probabilistic
      0.5 (and (holding ?t) (tried ?t) (not (hand-free)))
      0.5 (and (tried ?t))))

  ; Puts what it holds down on a switch's empty platform: most switches sink under one thing.
  (:action put-down
    :parameters (?t - thing ?s - switch ?d - door)
    :precondition (and (holding ?t) (robot-at ?s) (opens ?s ?d) (not (loaded ?s)))
    :effect (probabilistic
      0.8 (and (on ?t ?s) (loaded ?s) (pressed ?s) (open ?d) (hand-free) (not (holding ?t)))
      0.2 (and (on ?t ?s) (loaded ?s) (hand-free) (not (holding ?t)))))

  ; A second thing on a loaded platform presses even a stiff switch.
  (:action put-down-on-loaded
    :parameters (?t - thing ?s - switch ?d - door)
    :precondition (and (holding ?t) (robot-at ?s) (opens ?s ?d) (loaded ?s))
    :effect (and (on ?t ?s) (pressed ?s) (open ?d) (hand-free) (not (holding ?t))))

  ; Pushes a box onto a switch set flush with the floor, ending where the switch is.
  (:action push
    :parameters (?t - thing ?s - switch ?d - door)
    :precondition (and (robot-at ?t) (hand-free) (box ?t) (flush ?s) (opens ?s ?d))
    :effect (and (on ?t ?s) (loaded ?s) (pressed ?s) (open ?d) (robot-at ?s) (not (robot-at ?t))))

  ; Drives through an open door.
  (:action drive-through
    :parameters (?d - door)
    :precondition (and (robot-at ?d) (open ?d) (hand-free))
    :effect (and (beyond ?d))))
