/**
 * @class pqPTVProgressiveRefinement
 * @brief ParaView GUI component: refine "Path Traced Volume" representations while idle.
 *
 * The ParaView GUI renders a view only when something changes, so the path tracer would trace
 * one frame per change. This auto-start component (loaded with the plugin, GUI only; pvpython and
 * pvbatch never create it) keeps rendering, while the application is idle, every render view
 * that shows a visible "Path Traced Volume" representation with ProgressiveRefinement on whose
 * accumulation is not complete, and stops when every such representation is complete. It works
 * with ParaView's default settings ("Enable Streaming" is not needed).
 *
 * A representation is complete when vtkPTVRepresentationInformation, gathered from the render
 * server's root (the process that renders: the GUI itself in a builtin session, the pvserver in
 * client/server mode, whose progress the client's copy and its information properties do not
 * see), reports no need for refinement: the last render traced nothing or AccumulatedFrames
 * reached MaximumAccumulatedFrames (with client/server local rendering, below the view's
 * RemoteRenderThreshold, the client's copy renders: its information properties are read too).
 * As a safety cap, at most MaximumAccumulatedFrames renders
 * are issued for a view since the last render this component did not issue (any interaction,
 * property change, colour-map edit or resize renders the view and restarts the accumulation).
 *
 * Renders are issued from a zero-interval QTimer, i.e. once Qt has processed the pending events,
 * one StillRender per view and tick, never inside another render (ParaView processes events
 * while it renders) and never while a mouse button is pressed (the user is interacting:
 * ParaView renders then itself). Any render not issued here restarts the timer.
 */
#ifndef pqPTVProgressiveRefinement_h
#define pqPTVProgressiveRefinement_h

#include <QMap>
#include <QObject>
#include <QPointer>
#include <QTimer>

class pqRepresentation;
class pqView;

class pqPTVProgressiveRefinement : public QObject
{
  Q_OBJECT
  typedef QObject Superclass;

public:
  pqPTVProgressiveRefinement(QObject* parent = nullptr);
  ~pqPTVProgressiveRefinement() override;

  /// Called by the generated pqAutoStartInterface when the plugin is loaded in the GUI.
  void startup();
  /// Called before the application shuts down.
  void shutdown();

  /**
   * Whether @a view shows a visible Path Traced Volume representation that is still refining
   * (see the class documentation for the rule).
   */
  bool needsRefinement(pqView* view) const;

private Q_SLOTS:
  void onViewAdded(pqView* view);
  void onRepresentationAdded(pqRepresentation* repr);
  void onViewRemoved(pqView* view);
  void onBeginRender();
  void onEndRender();
  void onTimeout();

private:
  Q_DISABLE_COPY(pqPTVProgressiveRefinement)

  /// Renders this component issued for a view since the last render it did not issue.
  QMap<pqView*, int> OwnRenders;
  /// Set while this component renders a view (its endRender is then not a "change").
  pqView* RenderingView = nullptr;
  /// Renders of any view under way: ParaView processes Qt events during a render (progress),
  /// and this component never starts a render inside another one.
  int RendersInProgress = 0;
  QTimer Timer;
};

#endif
