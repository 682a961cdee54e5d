// The fuzzy supervisor's rule base (seed 002, a Chinese patent on fuzzy-PID for 3D-printer
// nozzles): Mamdani rules "if e is A and ec is B then Δkp is C, Δki is D, Δkd is E" over the
// seven sets {NB, NM, NS, ZO, PS, PM, PB}. The patent states only three principles and no table;
// the three 7×7 tables below are ours, written from those principles (docs/fuzzy_pid.md has the
// reasoning cell by cell). Plain integer data: the firmware and the host both include this.
//
// Universes (seed 002): inputs e and ec on −3…3, the seven input sets are triangles centred on
// −3, −2, …, 3 (set i centred on i − 3); outputs Δkp, Δki, Δkd on 0…3, the seven output sets
// are triangles centred on 0, 0.5, …, 3 (set k centred on k/2). A table cell holds the index k.
//
// Conventions: e = target − measured (positive below target), ec = de/dt. Rows are e (NB top),
// columns ec (NB left). e·ec > 0 means |e| is growing ("diverging", e.g. a fan step just hit);
// e·ec < 0 means the temperature is closing on the target ("converging", overshoot ahead).
#pragma once
#include <stdint.h>

namespace fuzzy {

enum Set : uint8_t { NB = 0, NM = 1, NS = 2, ZO = 3, PS = 4, PM = 5, PB = 6 };
constexpr int kSets = 7;

struct RuleTable {
  uint8_t out[kSets][kSets];  // out[e set][ec set] = output set index 0..6
};

// Δkp. |e| large: PB whatever ec does (principle 1: fast response). |e| medium: small (NS),
// smaller still when converging fast (overshoot ahead), ZO/PS when diverging (principle 2).
// |e| small: larger again (PS), PM/PB when diverging so disturbances meet a stiff loop,
// ZO when converging fast (principle 3). Point-symmetric: out[i][j] == out[6−i][6−j].
constexpr RuleTable kRulesKp = {{
    //  ec: NB  NM  NS  ZO  PS  PM  PB
    {PB, PB, PB, PB, PB, PB, PB},  // e NB
    {PS, ZO, ZO, NS, NS, NM, NM},  // e NM
    {PB, PM, PM, PS, PS, PS, ZO},  // e NS
    {PM, PM, PS, PS, PS, PM, PM},  // e ZO
    {ZO, PS, PS, PS, PM, PM, PB},  // e PS
    {NM, NM, NS, NS, ZO, ZO, PS},  // e PM
    {PB, PB, PB, PB, PB, PB, PB},  // e PB
}};

// Δki. |e| large: NB — no integration far from the target, the classic cause of overshoot
// (principle 1). |e| medium: ZO (medium), NS when converging fast. |e| small: PM, PB when
// diverging (a load step needs the integral to catch up), PS when converging fast; e ZO: PB
// so the steady state is held without offset (principle 3). Designed-in: non-increasing in |e|
// along every column, and point-symmetric.
constexpr RuleTable kRulesKi = {{
    //  ec: NB  NM  NS  ZO  PS  PM  PB
    {NB, NB, NB, NB, NB, NB, NB},  // e NB
    {ZO, ZO, ZO, ZO, ZO, NS, NS},  // e NM
    {PB, PB, PM, PM, PM, PM, PS},  // e NS
    {PB, PB, PB, PB, PB, PB, PB},  // e ZO
    {PS, PM, PM, PM, PM, PB, PB},  // e PS
    {NS, NS, ZO, ZO, ZO, ZO, ZO},  // e PM
    {NB, NB, NB, NB, NB, NB, NB},  // e PB
}};

// Δkd. |e| large: NB, NM when converging fast (principle 1: small kd). |e| medium: ZO (medium),
// PS when converging fast — "the response then depends on kd" — and NS when diverging
// (principle 2). |e| small: PB when |ec| is small, falling to NM as |ec| grows (principle 3,
// literally). Designed-in: in the |e|-small rows non-increasing in |ec|; point-symmetric.
constexpr RuleTable kRulesKd = {{
    //  ec: NB  NM  NS  ZO  PS  PM  PB
    {NB, NB, NB, NB, NB, NM, NM},  // e NB
    {NS, NS, ZO, ZO, ZO, PS, PS},  // e NM
    {NM, ZO, PM, PB, PM, ZO, NM},  // e NS
    {NM, ZO, PM, PB, PM, ZO, NM},  // e ZO
    {NM, ZO, PM, PB, PM, ZO, NM},  // e PS
    {PS, PS, ZO, ZO, ZO, NS, NS},  // e PM
    {NM, NM, NB, NB, NB, NB, NB},  // e PB
}};

}  // namespace fuzzy
