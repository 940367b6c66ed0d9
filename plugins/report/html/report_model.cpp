#include "report_model.hpp"

namespace lista::report {

const ObjectView* ReportModel::find(int id) const {
  for (const auto& o : objects)
    if (o.object->id == id) return &o;
  return nullptr;
}

ReportModel build_model(const ObjectSet& objects, const Groups* groups, const Matches* matches) {
  ReportModel model;
  model.missions = objects.missions;
  model.dynamics = objects.dynamics;
  for (const auto& object : objects.objects) {
    ObjectView view;
    view.object = &object;
    view.status = object.mission == 0 ? ChangeStatus::removed : ChangeStatus::added;
    if (groups) {
      for (size_t i = 0; i < groups->object_ids.size(); ++i)
        if (groups->object_ids[i] == object.id) {
          view.group = groups->group[i];
          if (i < groups->confidence.size()) view.confidence = groups->confidence[i];
        }
    }
    if (matches) {
      if (const ObjectChange* change = matches->find(object.id)) {
        view.status = change->status;
        view.match = change->match;
        view.confidence = change->confidence;
        if (change->has_transform) view.transform = change->transform;
        view.alternative_transforms = change->alternative_transforms;
        view.history = change->history;
      }
    }
    model.objects.push_back(view);
  }
  return model;
}

}  // namespace lista::report
