#pragma once
// An error that every rank of a decomposed run throws at the same point, decided from data
// all of them hold (placement too dense, a neuron that exhausts its attempts): the ranks
// end together and rank 0 reports `error`. Any other error is one rank's alone, met perhaps
// in the middle of collective work, and ends the job (app/run_command.cpp).
#include <exception>
#include <string>

namespace axg::distributed {

struct OnEveryRank : std::exception {
  explicit OnEveryRank(std::exception_ptr e) : error(std::move(e)) {
    try {
      std::rethrow_exception(error);
    } catch (const std::exception& x) {
      message = x.what();
    } catch (...) {
      message = "an error on every rank";
    }
  }
  const char* what() const noexcept override { return message.c_str(); }
  std::exception_ptr error;
  std::string message;
};

// Calls fn; what it throws is rethrown as OnEveryRank (fn must decide only from data every
// rank holds alike).
template <class Fn>
void on_every_rank(Fn&& fn) {
  try {
    fn();
  } catch (...) {
    throw OnEveryRank(std::current_exception());
  }
}

}  // namespace axg::distributed
