// MANYWORLDS_VISIT_FIELDS(f, a, b, c) is `f("a", a); f("b", b); f("c", c);`:
// the body of a config's VisitFields (config keys are the member names), so
// each key is written once and cannot disagree with its member.
//
//   template <class F>
//   void VisitFields(F&& f) {
//     MANYWORLDS_VISIT_FIELDS(f, hidden_dim, num_layers, seed);
//   }
//
// At least 64 fields (the rescans below); past the limit the macro stays
// unexpanded, a compile error, never a field silently left out.
#ifndef MANYWORLDS_CORE_VISIT_FIELDS_H_
#define MANYWORLDS_CORE_VISIT_FIELDS_H_

#define MANYWORLDS_VISIT_FIELDS(f, ...) \
  __VA_OPT__(MANYWORLDS_VF_X(MANYWORLDS_VF_NEXT(f, __VA_ARGS__)))

// A recursion the preprocessor allows: each rescan of MANYWORLDS_VF_X
// visits one more field.
#define MANYWORLDS_VF_NEXT(f, field, ...) \
  f(#field, field) __VA_OPT__(; MANYWORLDS_VF_AGAIN MANYWORLDS_VF_PARENS(f, __VA_ARGS__))
#define MANYWORLDS_VF_AGAIN() MANYWORLDS_VF_NEXT
#define MANYWORLDS_VF_PARENS ()
#define MANYWORLDS_VF_X(...) \
  MANYWORLDS_VF_X3(MANYWORLDS_VF_X3(MANYWORLDS_VF_X3(MANYWORLDS_VF_X3(__VA_ARGS__))))
#define MANYWORLDS_VF_X3(...) \
  MANYWORLDS_VF_X2(MANYWORLDS_VF_X2(MANYWORLDS_VF_X2(MANYWORLDS_VF_X2(__VA_ARGS__))))
#define MANYWORLDS_VF_X2(...) \
  MANYWORLDS_VF_X1(MANYWORLDS_VF_X1(MANYWORLDS_VF_X1(MANYWORLDS_VF_X1(__VA_ARGS__))))
#define MANYWORLDS_VF_X1(...) __VA_ARGS__

#endif  // MANYWORLDS_CORE_VISIT_FIELDS_H_
