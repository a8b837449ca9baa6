// Questions about patches a rank does not hold, answered by the ranks that own them: the
// discretisation estimate's rays land anywhere in the scene, and a value of every patch of the
// scene on every rank (ρ times H's gradient: 72 B a patch) is what a rank cannot afford at scale.
#pragma once

#include <mpi.h>

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "partition/partition.h"

namespace radiosity::partition {

/// Where every rank's block of patches begins (rank blocks are in id order, cut by count or by
/// cost), to find the owner of any patch. Collective to make.
class RankBlocks {
 public:
  RankBlocks(MPI_Comm comm, PatchRange owned) {
    int ranks = 1;
    MPI_Comm_size(comm, &ranks);
    begin_.resize(static_cast<size_t>(ranks));
    MPI_Allgather(&owned.begin, 1, MPI_INT64_T, begin_.data(), 1, MPI_INT64_T, comm);
  }

  int ownerOf(int64_t patch) const {
    return static_cast<int>(std::upper_bound(begin_.begin(), begin_.end(), patch) -
                            begin_.begin()) -
           1;
  }
  int ranks() const { return static_cast<int>(begin_.size()); }

 private:
  std::vector<int64_t> begin_;
};

/// Each of this rank's `questions` (a struct with an int64_t `patch`) sent to the rank owning its
/// patch, answered there by `answer(question)` and returned in the questions' order. Every rank
/// calls it the same number of times (with no questions where it has none). Collective; the
/// answers are whatever `answer` gives on the owner, so the same on any number of ranks.
template <class Answer, class Question, class AnswerOf>
std::vector<Answer> askOwners(MPI_Comm comm, const RankBlocks& blocks,
                              const std::vector<Question>& questions, const AnswerOf& answer) {
  static_assert(std::is_trivially_copyable_v<Question> && std::is_trivially_copyable_v<Answer>);
  const int ranks = blocks.ranks();
  // The questions grouped by owner, in their order within each group.
  std::vector<int> sendCount(ranks, 0), sendOffset(ranks, 0), owner(questions.size());
  for (size_t q = 0; q < questions.size(); ++q)
    ++sendCount[owner[q] = blocks.ownerOf(questions[q].patch)];
  for (int r = 1; r < ranks; ++r) sendOffset[r] = sendOffset[r - 1] + sendCount[r - 1];
  std::vector<int> place(questions.size());
  std::vector<Question> sent(questions.size());
  {
    std::vector<int> next = sendOffset;
    for (size_t q = 0; q < questions.size(); ++q) sent[place[q] = next[owner[q]]++] = questions[q];
  }
  std::vector<int> receiveCount(ranks), receiveOffset(ranks, 0);
  MPI_Alltoall(sendCount.data(), 1, MPI_INT, receiveCount.data(), 1, MPI_INT, comm);
  for (int r = 1; r < ranks; ++r) receiveOffset[r] = receiveOffset[r - 1] + receiveCount[r - 1];
  const int received = ranks > 0 ? receiveOffset[ranks - 1] + receiveCount[ranks - 1] : 0;

  MPI_Datatype questionType, answerType;
  MPI_Type_contiguous(static_cast<int>(sizeof(Question)), MPI_BYTE, &questionType);
  MPI_Type_contiguous(static_cast<int>(sizeof(Answer)), MPI_BYTE, &answerType);
  MPI_Type_commit(&questionType);
  MPI_Type_commit(&answerType);
  std::vector<Question> asked(static_cast<size_t>(received));
  MPI_Alltoallv(sent.data(), sendCount.data(), sendOffset.data(), questionType, asked.data(),
                receiveCount.data(), receiveOffset.data(), questionType, comm);
  sent = {};
  std::vector<Answer> given(asked.size()), back(questions.size());
  for (size_t q = 0; q < asked.size(); ++q) given[q] = answer(asked[q]);
  MPI_Alltoallv(given.data(), receiveCount.data(), receiveOffset.data(), answerType, back.data(),
                sendCount.data(), sendOffset.data(), answerType, comm);
  MPI_Type_free(&questionType);
  MPI_Type_free(&answerType);
  std::vector<Answer> out(questions.size());
  for (size_t q = 0; q < questions.size(); ++q) out[q] = back[place[q]];
  return out;
}

}  // namespace radiosity::partition
