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
 * The rule for "complete":
 * - builtin session (the GUI process renders): the representation's information properties
 *   LastRenderTraced and AccumulatedFrames, read after each render: complete when the last
 *   render traced nothing or AccumulatedFrames >= MaximumAccumulatedFrames;
 * - remote session (pvserver renders; the client's copy of the representation never renders):
 *   a client-side budget, the number of renders this component issued for the view since the
 *   last render it did not issue (any interaction, property change, colour-map edit or resize
 *   renders the view, and every such change restarts the mapper's accumulation): complete when
 *   that count reaches MaximumAccumulatedFrames. A render that did not change anything resets
 *   the budget too; the extra renders then trace nothing on the server (converged) and only
 *   deliver the image again.
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
