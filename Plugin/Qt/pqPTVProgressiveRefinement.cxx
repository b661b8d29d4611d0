#include "pqPTVProgressiveRefinement.h"

#include "pqApplicationCore.h"
#include "pqRepresentation.h"
#include "pqServer.h"
#include "pqServerManagerModel.h"
#include "pqView.h"
#include "vtkNew.h"
#include "vtkPTVRepresentationInformation.h"
#include "vtkPVSession.h"
#include "vtkSMPropertyHelper.h"
#include "vtkSMProxy.h"
#include "vtkSMSession.h"
#include "vtkSMViewProxy.h"

#include <QApplication>

namespace
{
/// The representation type added by Plugin/PathTracedVolumeRepresentation.xml.
const char* const PTVRepresentationType = "Path Traced Volume";

/**
 * The proxy of a visible representation shown as "Path Traced Volume" with ProgressiveRefinement
 * on, or nullptr. The Path Traced Volume sub-proxy's properties are exposed on it.
 */
vtkSMProxy* activePathTracedProxy(pqRepresentation* repr)
{
  vtkSMProxy* proxy = repr ? repr->getProxy() : nullptr;
  if (!proxy || !repr->isVisible() || !proxy->GetProperty("Representation") ||
    !proxy->GetProperty("ProgressiveRefinement") || !proxy->GetProperty("AccumulatedFrames"))
  {
    return nullptr;
  }
  const char* type = vtkSMPropertyHelper(proxy, "Representation").GetAsString();
  if (!type || QString(type) != PTVRepresentationType ||
    vtkSMPropertyHelper(proxy, "ProgressiveRefinement").GetAsInt() == 0)
  {
    return nullptr;
  }
  return proxy;
}
}

//------------------------------------------------------------------------------
pqPTVProgressiveRefinement::pqPTVProgressiveRefinement(QObject* parentObject)
  : Superclass(parentObject)
{
  this->Timer.setInterval(0);
  this->Timer.setSingleShot(false);
  QObject::connect(&this->Timer, &QTimer::timeout, this, &pqPTVProgressiveRefinement::onTimeout);
}

//------------------------------------------------------------------------------
pqPTVProgressiveRefinement::~pqPTVProgressiveRefinement() = default;

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::startup()
{
  pqApplicationCore* core = pqApplicationCore::instance();
  if (!core)
  {
    return;
  }
  pqServerManagerModel* model = core->getServerManagerModel();
  QObject::connect(
    model, &pqServerManagerModel::viewAdded, this, &pqPTVProgressiveRefinement::onViewAdded);
  QObject::connect(
    model, &pqServerManagerModel::viewRemoved, this, &pqPTVProgressiveRefinement::onViewRemoved);
  QObject::connect(model, &pqServerManagerModel::representationAdded, this,
    &pqPTVProgressiveRefinement::onRepresentationAdded);
  for (pqRepresentation* repr : model->findItems<pqRepresentation*>())
  {
    this->onRepresentationAdded(repr);
  }
  // Views that exist already (the plugin loaded after they were created).
  for (pqView* view : model->findItems<pqView*>())
  {
    this->onViewAdded(view);
  }
  this->Timer.start();
}

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::shutdown()
{
  this->Timer.stop();
  pqApplicationCore* core = pqApplicationCore::instance();
  if (core)
  {
    QObject::disconnect(core->getServerManagerModel(), nullptr, this, nullptr);
  }
  for (auto it = this->OwnRenders.begin(); it != this->OwnRenders.end(); ++it)
  {
    QObject::disconnect(it.key(), nullptr, this, nullptr);
  }
  this->OwnRenders.clear();
}

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::onViewAdded(pqView* view)
{
  if (!view || this->OwnRenders.contains(view))
  {
    return;
  }
  this->OwnRenders.insert(view, 0);
  QObject::connect(view, &pqView::beginRender, this, &pqPTVProgressiveRefinement::onBeginRender);
  QObject::connect(view, &pqView::endRender, this, &pqPTVProgressiveRefinement::onEndRender);
}

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::onRepresentationAdded(pqRepresentation* repr)
{
  // In the GUI, still renders other than captures trace one frame each (the idle refinement
  // goes on from there), so the window never freezes for a converging still render.
  vtkSMProxy* proxy = repr ? repr->getProxy() : nullptr;
  if (proxy && proxy->GetProperty("InteractiveSession") &&
    vtkSMPropertyHelper(proxy, "InteractiveSession").GetAsInt() == 0)
  {
    vtkSMPropertyHelper(proxy, "InteractiveSession").Set(1);
    proxy->UpdateVTKObjects();
  }
}

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::onViewRemoved(pqView* view)
{
  this->OwnRenders.remove(view);
  if (view)
  {
    QObject::disconnect(view, nullptr, this, nullptr);
  }
}

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::onBeginRender()
{
  ++this->RendersInProgress;
}

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::onEndRender()
{
  if (this->RendersInProgress > 0)
  {
    --this->RendersInProgress;
  }
  pqView* view = qobject_cast<pqView*>(this->sender());
  if (!view || view == this->RenderingView)
  {
    return;
  }
  // Rendered by someone else: something may have changed, which restarts the accumulation.
  this->OwnRenders[view] = 0;
  if (!this->Timer.isActive())
  {
    this->Timer.start();
  }
}

//------------------------------------------------------------------------------
bool pqPTVProgressiveRefinement::needsRefinement(pqView* view) const
{
  if (!view || !view->getViewProxy())
  {
    return false;
  }
  vtkSMSession* session = view->getServer() ? view->getServer()->session() : nullptr;
  if (!session)
  {
    return false;
  }
  for (pqRepresentation* repr : view->getRepresentations())
  {
    vtkSMProxy* proxy = activePathTracedProxy(repr);
    if (!proxy)
    {
      continue;
    }
    // Safety cap: never more renders since the last change than frames to accumulate.
    const int maximum = vtkSMPropertyHelper(proxy, "MaximumAccumulatedFrames").GetAsInt();
    if (this->OwnRenders.value(view, 0) >= maximum)
    {
      continue;
    }
    // The progress of the copy that renders (the server's in client/server mode; the client's
    // copy and its information properties never render there).
    vtkNew<vtkPTVRepresentationInformation> info;
    session->GatherInformation(vtkPVSession::RENDER_SERVER_ROOT, info, proxy->GetGlobalID());
    if (info->GetFound() && info->GetNeedsRefinement())
    {
      return true;
    }
    // Client/server with local rendering (data under the view's RemoteRenderThreshold): the
    // client's copy renders; its information properties tell.
    if (view->getServer()->isRemote())
    {
      proxy->UpdatePropertyInformation();
      if (vtkSMPropertyHelper(proxy, "LastRenderTraced").GetAsInt() &&
        vtkSMPropertyHelper(proxy, "AccumulatedFrames").GetAsInt() < maximum)
      {
        return true;
      }
    }
  }
  return false;
}

//------------------------------------------------------------------------------
void pqPTVProgressiveRefinement::onTimeout()
{
  if (this->RendersInProgress > 0 || QApplication::mouseButtons() != Qt::NoButton)
  {
    // A render is under way (this tick runs from its event processing) or the user is
    // interacting, and ParaView renders by itself: look again a little later.
    this->Timer.setInterval(50);
    return;
  }
  this->Timer.setInterval(0);
  bool pending = false;
  const QList<pqView*> views = this->OwnRenders.keys();
  for (pqView* view : views)
  {
    if (!this->needsRefinement(view))
    {
      continue;
    }
    QPointer<pqView> guard(view);
    this->RenderingView = view;
    view->getViewProxy()->StillRender(); // synchronous: its endRender is ours
    this->RenderingView = nullptr;
    if (guard && this->OwnRenders.contains(view))
    {
      ++this->OwnRenders[view];
      pending = true;
    }
  }
  if (!pending)
  {
    this->Timer.stop();
  }
}
